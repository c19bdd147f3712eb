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
