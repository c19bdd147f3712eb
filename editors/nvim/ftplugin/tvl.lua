vim.bo.commentstring = '// %s'
vim.bo.comments = 's1:/*,mb:*,ex:*/,://'
vim.bo.shiftwidth = vim.bo.shiftwidth > 0 and vim.bo.shiftwidth or 2
