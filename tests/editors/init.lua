-- init.lua for the headless-Neovim end-to-end test: the same lines the README gives users,
-- with the repository path and the server command taken from the environment.
local repo = assert(os.getenv('TVL_LSP_REPO'), 'TVL_LSP_REPO must be set')
vim.opt.runtimepath:append(repo .. '/editors/nvim')
local cmd = os.getenv('TVL_LSP_CMD') -- a JSON list, or words: "/path/.venv/bin/python -m tvl_lsp"
if cmd and cmd ~= '' then
  local argv = cmd:sub(1, 1) == '[' and vim.json.decode(cmd) or vim.split(cmd, ' ', { trimempty = true })
  vim.lsp.config('tvl_lsp', { cmd = argv })
end
vim.lsp.enable('tvl_lsp')
