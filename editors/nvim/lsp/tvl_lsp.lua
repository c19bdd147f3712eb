-- tvl-lsp: the language server for TVL feature models and the ROS launch files they configure.
-- Neovim 0.11+: put editors/nvim on 'runtimepath', then vim.lsp.enable('tvl_lsp').
-- Override any field with vim.lsp.config('tvl_lsp', { ... }), for instance
--   vim.lsp.config('tvl_lsp', { cmd = { '/path/to/.venv/bin/tvl-lsp' } })
-- or set vim.g.tvl_lsp_cmd = { ... } / vim.g.tvl_lsp_python = '/path/to/python' before enabling.

local function default_cmd()
  if type(vim.g.tvl_lsp_cmd) == 'table' then
    return vim.g.tvl_lsp_cmd
  end
  if vim.g.tvl_lsp_python then
    return { vim.g.tvl_lsp_python, '-m', 'tvl_lsp' }
  end
  -- when it is not on PATH, Neovim says "Spawning language server with cmd: `tvl-lsp` failed"
  return { 'tvl-lsp' }
end

local function is_workspace_marker(name)
  return name == '.catkin_workspace' or name == '.catkin_tools' or name:match('^haros.*%.ya?ml$') ~= nil
end

---@type vim.lsp.Config
return {
  cmd = default_cmd(),
  filetypes = { 'tvl', 'roslaunch' },
  -- the catkin workspace (or the folder of the HAROS project files), else the git repository,
  -- else the file's folder
  root_dir = function(bufnr, on_dir)
    local root = vim.fs.root(bufnr, is_workspace_marker) or vim.fs.root(bufnr, { '.git' })
    if not root then
      local name = vim.api.nvim_buf_get_name(bufnr)
      root = name ~= '' and vim.fs.dirname(name) or vim.fn.getcwd()
    end
    on_dir(root)
  end,
  settings = {
    ['tvl-lsp'] = {
      -- per-code severity, e.g. { ['missing-arg'] = 'warning', ['dead-feature'] = 'off' }
      diagnostics = vim.empty_dict(),
      count = { timeBudget = 10 },
      generate = { folder = '', limit = 100 },
    },
  },
  before_init = function(params, config)
    -- the server reads the same settings from initializationOptions at start-up
    params.initializationOptions = { ['tvl-lsp'] = (config.settings or {})['tvl-lsp'] }
  end,
}
