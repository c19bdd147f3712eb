-- ROS launch files are XML: reuse the xml syntax, indentation and tree-sitter parser.
vim.bo.commentstring = '<!-- %s -->'
if vim.bo.syntax == '' or vim.bo.syntax == 'roslaunch' then
  vim.bo.syntax = 'xml'
end
pcall(vim.treesitter.language.register, 'xml', 'roslaunch')
