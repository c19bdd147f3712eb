-- ROS launch files are XML: reuse the xml filetype plugin (comments, matchit pairs, ...).
vim.cmd('runtime! ftplugin/xml.vim ftplugin/xml_*.vim ftplugin/xml/*.vim')
vim.bo.commentstring = '<!-- %s -->'
-- a tree-sitter xml parser, if installed, serves roslaunch too
pcall(vim.treesitter.language.register, 'xml', 'roslaunch')
