-- tvl-lsp: the language server for TVL feature models and the ROS launch files they configure
-- (ROS 1 XML; ROS 2 XML, YAML and Python).
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

-- a colcon (ROS 2) workspace has no marker file: it is the folder whose src holds the packages
-- (a folder with a package.xml is a package, and its src its sources)
local function is_colcon_src(name, path)
  return name == 'src' and vim.fn.filereadable(path .. '/package.xml') == 0
end

local function is_workspace_marker(name)
  return name == '.catkin_workspace' or name == '.catkin_tools' or name:match('^haros.*%.ya?ml$') ~= nil
end

-- ROS 2 launch files in Python and YAML keep their filetypes (python, yaml: their highlighting
-- and other servers); tvl-lsp attaches to them by name only, never to other Python or YAML
local LAUNCH_NAMES = { '%.launch%.py$', '_launch%.py$', '%.launch%.ya?ml$', '_launch%.ya?ml$' }

local function is_launch_file(name)
  for _, pat in ipairs(LAUNCH_NAMES) do
    if name:match(pat) then
      return true
    end
  end
  return false
end

---@type vim.lsp.Config
return {
  cmd = default_cmd(),
  filetypes = { 'tvl', 'roslaunch', 'python', 'yaml' },
  -- the catkin workspace (or the folder of the HAROS project files), else the git repository,
  -- else the colcon workspace (the parent of src), else the file's folder (as the server finds
  -- a workspace); a python or yaml buffer only when it is a launch file
  root_dir = function(bufnr, on_dir)
    local ft = vim.bo[bufnr].filetype
    if (ft == 'python' or ft == 'yaml') and not is_launch_file(vim.api.nvim_buf_get_name(bufnr)) then
      return
    end
    local root = vim.fs.root(bufnr, is_workspace_marker) or vim.fs.root(bufnr, { '.git' })
      or vim.fs.root(bufnr, is_colcon_src)
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
