-- Filetypes for tvl-lsp: TVL models and ROS 1 launch files (XML, highlighted as xml).
vim.filetype.add({
  extension = {
    tvl = 'tvl',
    launch = 'roslaunch',
    test = function(path, bufnr)
      -- rostest files are launch XML; other *.test files keep their usual detection
      local first = vim.api.nvim_buf_get_lines(bufnr, 0, 5, false)
      for _, line in ipairs(first) do
        if line:find('<launch') or line:find('<%?xml') then
          return 'roslaunch'
        end
      end
    end,
  },
  pattern = {
    ['.*%.launch%.xml'] = 'roslaunch',
    ['.*_launch%.xml'] = 'roslaunch',
  },
})
