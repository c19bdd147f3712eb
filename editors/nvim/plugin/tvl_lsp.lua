-- User commands for tvl-lsp's configurator and configuration generation (see lua/tvl_lsp).
if vim.g.loaded_tvl_lsp_commands then
  return
end
vim.g.loaded_tvl_lsp_commands = true

local function tvl()
  return require('tvl_lsp')
end

vim.api.nvim_create_user_command('TvlInclude', function(o)
  tvl().include(o.args)
end, { nargs = '?', desc = 'tvl-lsp configurator: include a feature (default: the word under the cursor)' })
vim.api.nvim_create_user_command('TvlExclude', function(o)
  tvl().exclude(o.args)
end, { nargs = '?', desc = 'tvl-lsp configurator: exclude a feature (default: the word under the cursor)' })
vim.api.nvim_create_user_command('TvlReset', function(o)
  tvl().reset(o.args)
end, { nargs = '?', desc = 'tvl-lsp configurator: forget one decision, or all' })
vim.api.nvim_create_user_command('TvlCount', function()
  tvl().count()
end, { desc = 'tvl-lsp configurator: count the remaining products' })
vim.api.nvim_create_user_command('TvlProducts', function(o)
  tvl().list_products(tonumber(o.args))
end, { nargs = '?', desc = 'tvl-lsp configurator: list the remaining products' })
vim.api.nvim_create_user_command('TvlGenerate', function(o)
  tvl().generate(o.args)
end, {
  nargs = '?',
  complete = function()
    return { 'one', 'completions', 'all' }
  end,
  desc = 'tvl-lsp: generate configuration launch files (one | completions | all)',
})

-- Neovim 0.11 only writes to its LSP log when a server command cannot be run: say it where
-- the user looks, once, when a TVL model or launch file is opened.
vim.api.nvim_create_autocmd('FileType', {
  pattern = { 'tvl', 'roslaunch' },
  group = vim.api.nvim_create_augroup('tvl_lsp_check_cmd', { clear = true }),
  callback = function()
    if vim.g.tvl_lsp_warned then
      return
    end
    local ok, cfg = pcall(function()
      return vim.lsp.config['tvl_lsp']
    end)
    local cmd = ok and cfg and cfg.cmd
    if type(cmd) == 'table' and cmd[1] and vim.fn.executable(cmd[1]) ~= 1 then
      vim.g.tvl_lsp_warned = true
      vim.schedule(function()
        vim.notify(
          string.format(
            "tvl-lsp: cannot run %q. Install the server (pip install /path/to/tvl-lsp) and put it on PATH, or set vim.lsp.config('tvl_lsp', { cmd = { '/path/to/.venv/bin/tvl-lsp' } })",
            cmd[1]
          ),
          vim.log.levels.ERROR
        )
      end)
    end
  end,
})
