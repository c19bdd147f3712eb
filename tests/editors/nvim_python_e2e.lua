-- Headless Neovim end-to-end test of tvl-lsp on a ROS 2 Python launch file (the rover of
-- tests/data/ros2py_editor/ws), with the configuration in editors/nvim.
--
-- Run by tests/test_editors_nvim.py as
--   nvim --headless -n -i NONE -u tests/editors/init.lua -c "luafile tests/editors/nvim_python_e2e.lua"
-- with TVL_E2E_WS (a scratch copy of the workspace) and TVL_E2E_OUT (a JSON result file). Steps:
-- open rover.launch.py (filetype python, tvl_lsp attached); wait for the four planted problems;
-- hover a feature argument for its product count; apply the quick fix that adds the missing
-- DeclareLaunchArgument; open an ordinary Python module: tvl_lsp does not attach to it.

local LAUNCH = 'src/rover/launch/rover.launch.py'
local PLAIN = 'src/rover/rover/util.py'
local EXPECTED_CODES = { 'dead-element', 'duplicate-node', 'missing-arg', 'unmatched-arg' }
local HOVER_LINE, HOVER_WORD = 21, "'Camera'" -- DeclareLaunchArgument('Camera', ...)
local HOVER_MUST_CONTAIN = { '12 of 24 products', "DeclareLaunchArgument('Camera')" }
local FIX_TITLE = "Add DeclareLaunchArgument('Teleop')"
local EXPECTED_INSERTED_LINE = "        DeclareLaunchArgument('Teleop', default_value='false'),"
local EXPECTED_AFTER_LINE = "        DeclareLaunchArgument('Sonar', default_value='false'),"
local START_TIMEOUT_MS, DIAG_TIMEOUT_MS, REQUEST_TIMEOUT_MS = 30000, 60000, 30000

local ws = assert(os.getenv('TVL_E2E_WS'), 'TVL_E2E_WS must be set')
local out_path = assert(os.getenv('TVL_E2E_OUT'), 'TVL_E2E_OUT must be set')
local result = { checks = {}, log = {} }

local function check(name, ok, detail)
  table.insert(result.checks, { name = name, ok = ok and true or false, detail = detail })
  io.stderr:write(string.format('%s %s\n', ok and 'PASS' or 'FAIL', name))
  return ok
end

local function finish()
  local ok = #result.checks > 0
  for _, c in ipairs(result.checks) do
    ok = ok and c.ok
  end
  result.ok = ok
  local fh = assert(io.open(out_path, 'w'))
  fh:write(vim.json.encode(result))
  fh:close()
  for _, client in ipairs(vim.lsp.get_clients()) do
    client:stop(true)
  end
  vim.wait(3000, function()
    return #vim.lsp.get_clients() == 0
  end, 50)
  vim.cmd(ok and 'qall!' or 'cquit! 1')
end

local function codes(buf)
  local seen, out = {}, {}
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if not seen[d.code] then
      seen[d.code] = true
      table.insert(out, d.code)
    end
  end
  table.sort(out)
  return out
end

local function find_diag(buf, code)
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if d.code == code then
      return d
    end
  end
end

local function hover_text(client, buf)
  local text = vim.api.nvim_buf_get_lines(buf, HOVER_LINE - 1, HOVER_LINE, false)[1] or ''
  local col = text:find(HOVER_WORD, 1, true)
  if not col then
    return nil
  end
  local resp = client:request_sync('textDocument/hover', {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    position = { line = HOVER_LINE - 1, character = col + 1 },
  }, REQUEST_TIMEOUT_MS, buf)
  local c = resp and resp.result and resp.result.contents
  return c and (type(c) == 'string' and c or c.value) or nil
end

local function contains_all(text, needles)
  if type(text) ~= 'string' then
    return false
  end
  for _, s in ipairs(needles) do
    if not text:find(s, 1, true) then
      return false
    end
  end
  return true
end

local ok, err = xpcall(function()
  vim.cmd.edit(vim.fn.fnameescape(vim.fs.joinpath(ws, LAUNCH)))
  local buf = vim.api.nvim_get_current_buf()
  check('a Python launch file keeps the python filetype', vim.bo[buf].filetype == 'python', vim.bo[buf].filetype)
  local client
  vim.wait(START_TIMEOUT_MS, function()
    client = vim.lsp.get_clients({ bufnr = buf, name = 'tvl_lsp' })[1]
    return client ~= nil and client.initialized
  end, 50)
  if not check('tvl_lsp attached to the launch file', client ~= nil and client.initialized) then
    return
  end
  check('root is the workspace', vim.fs.normalize(client.root_dir or '') == vim.fs.normalize(ws), client.root_dir)

  local got = vim.wait(DIAG_TIMEOUT_MS, function()
    return vim.deep_equal(codes(buf), EXPECTED_CODES)
  end, 50)
  result.codes = codes(buf)
  check('the four planted problems reported', got, result.codes)

  local text
  vim.wait(DIAG_TIMEOUT_MS, function()
    text = hover_text(client, buf)
    return contains_all(text, HOVER_MUST_CONTAIN)
  end, 250)
  result.hover = text
  check('hover on a feature argument shows its product count', contains_all(text, HOVER_MUST_CONTAIN), text)

  local missing = find_diag(buf, 'missing-arg')
  local lsp_diag = missing and missing.user_data and missing.user_data.lsp
  if not check('missing-arg has its LSP diagnostic', lsp_diag ~= nil) then
    return
  end
  local resp = client:request_sync('textDocument/codeAction', {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    range = lsp_diag.range,
    context = { diagnostics = { lsp_diag }, only = { 'quickfix' }, triggerKind = 1 },
  }, REQUEST_TIMEOUT_MS, buf)
  local action, titles = nil, {}
  for _, a in ipairs(resp and resp.result or {}) do
    table.insert(titles, a.title)
    if a.title == FIX_TITLE then
      action = a
    end
  end
  if not check('the quick fix is offered', action ~= nil, titles) then
    return
  end
  local before = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
  vim.lsp.util.apply_workspace_edit(action.edit, client.offset_encoding)
  local after = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
  local at
  for i, l in ipairs(after) do
    if l == EXPECTED_INSERTED_LINE then
      at = i
    end
  end
  check('DeclareLaunchArgument inserted after the last one, formatted like it',
    at ~= nil and after[at - 1] == EXPECTED_AFTER_LINE and #after == #before + 1,
    at and { before = after[at - 1], line = after[at] } or after)
  local gone = vim.wait(DIAG_TIMEOUT_MS, function()
    return find_diag(buf, 'missing-arg') == nil and #codes(buf) == 3
  end, 50)
  check('missing-arg gone after the fix', gone, codes(buf))

  vim.cmd.edit(vim.fn.fnameescape(vim.fs.joinpath(ws, PLAIN)))
  local pbuf = vim.api.nvim_get_current_buf()
  vim.wait(2000, function()
    return false
  end, 100)
  check('ordinary Python: tvl_lsp does not attach', vim.bo[pbuf].filetype == 'python'
    and vim.lsp.get_clients({ bufnr = pbuf, name = 'tvl_lsp' })[1] == nil)
end, debug.traceback)
if not ok then
  check('harness ran without error', false, err)
end
finish()
