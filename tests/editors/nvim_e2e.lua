-- Headless Neovim end-to-end test of tvl-lsp on the test workspace (the scout robot of tests/data/ws).
--
-- Run by tests/test_editors_nvim.py as
--   nvim --headless -n -i NONE -u tests/editors/init.lua -c "luafile tests/editors/nvim_e2e.lua"
-- with TVL_E2E_WS (a scratch copy of the test workspace, tests/testenv.py) and TVL_E2E_OUT (a JSON
-- result file). Steps: open the scout's generic launch file; wait for the server's diagnostics and compare them
-- with EXPECTED_DIAGNOSTICS; hover a feature arg and look for the product count; delete one
-- feature arg, wait for the missing-arg diagnostic, apply its quick fix, check the buffer and
-- that the diagnostic is gone.

------------------------------------------------------------------------------------------------
-- EXPECTATIONS (tune here)
------------------------------------------------------------------------------------------------
local LAUNCH = 'src/scout/launch/generic.launch' -- relative to the workspace
-- Every diagnostic the server must report on the untouched file, 1-based line; the server
-- must report nothing else (after SETTLE_MS of quiet).
local EXPECTED_DIAGNOSTICS = {
  -- `$(arg stereo_cam)` in the Simulation branch: no such arg (the feature is Stereo_cam)
  { code = 'undefined-arg', line = 61, contains = 'stereo_cam' },
  -- `$(arg webcam)` in the same value: undeclared too, its own diagnostic
  { code = 'undefined-arg', line = 61, contains = "'webcam'" },
}
-- Hover on a feature arg: where, and what the text must contain.
local HOVER_LINE, HOVER_WORD = 8, 'Simulation' -- <arg name="Simulation" doc="..."/>
local HOVER_MUST_CONTAIN = { '384 of 1152' } -- Simulation is in 384 of the 1152 products
-- Hover on the root feature's arg: the total.
local ROOT_HOVER_LINE, ROOT_HOVER_WORD = 3, 'Scout'
local ROOT_HOVER_MUST_CONTAIN = { '1152 products' }
-- The model: opened after the launch file; its root hovered.
local MODEL = 'src/scout/launch/generic.tvl'
local MODEL_HOVER_LINE, MODEL_HOVER_WORD = 4, 'Scout' -- root Scout {
local MODEL_HOVER_MUST_CONTAIN = { '1152 products' }
local MODEL_EXPECTED_DIAGNOSTICS = 0
-- The quick fix: delete this feature's <arg> line, expect a missing-arg diagnostic naming it,
-- apply the fix whose title names it, and expect this line right after the last top-level arg.
local REMOVE_ARG = 'Map'
local MISSING_CODE = 'missing-arg'
local EXPECTED_INSERTED_LINE = '  <arg name="Map"/>'
local EXPECTED_AFTER_LINE = '  <arg name="Planner"/>'
-- The configurator and the generation, through editors/nvim/lua/tvl_lsp (the :Tvl* commands):
-- include this feature and expect this many remaining products, then reset;
local CONFIG_FEATURE, CONFIG_REMAINING, CONFIG_TOTAL = 'Simulation', '384', '1152'
-- generate one configuration launch file from the launch file and expect it on disk, in
-- GENERATE_FOLDER (relative to the launch file's package folder), with these lines.
local GENERATE_MODE, GENERATE_FILES = 'one', 1
local GENERATE_FOLDER = 'src/scout/configs'
local GENERATE_MUST_CONTAIN = { '<include file="$(find scout)/launch/generic.launch">', '<arg name="Scout" value="true"/>' }
-- Timing
local START_TIMEOUT_MS = 30000
local DIAG_TIMEOUT_MS = 60000
local SETTLE_MS = 2000
local REQUEST_TIMEOUT_MS = 30000
local HOVER_TIMEOUT_MS = 30000
------------------------------------------------------------------------------------------------

local ws = assert(os.getenv('TVL_E2E_WS'), 'TVL_E2E_WS must be set')
local out_path = assert(os.getenv('TVL_E2E_OUT'), 'TVL_E2E_OUT must be set')
local result = { checks = {}, log = {} }

local function log(fmt, ...)
  local msg = string.format(fmt, ...)
  table.insert(result.log, msg)
  io.stderr:write(msg .. '\n')
end

local function check(name, ok, detail)
  table.insert(result.checks, { name = name, ok = ok and true or false, detail = detail })
  log('%s %s%s', ok and 'PASS' or 'FAIL', name, detail and (': ' .. vim.inspect(detail)) or '')
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

-- Whatever goes wrong below (an error in this script included), write the result and quit.
local function step(fn)
  local ok, err = xpcall(fn, debug.traceback)
  if not ok then
    check('harness ran without error', false, err)
  end
  finish()
end

local function diag_summary(buf)
  local items = {}
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    table.insert(items, {
      code = d.code,
      line = d.lnum + 1,
      col = d.col + 1,
      severity = d.severity,
      message = d.message,
      source = d.source,
    })
  end
  table.sort(items, function(a, b)
    return a.line < b.line or (a.line == b.line and tostring(a.code) < tostring(b.code))
  end)
  return items
end

local function find_diag(buf, code, pred)
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if d.code == code and (not pred or pred(d)) then
      return d
    end
  end
end

-- Wait until fn() is true, then until the buffer's diagnostics stop changing for SETTLE_MS.
local function wait_settled(buf, timeout, fn)
  local ok = vim.wait(timeout, fn, 50)
  local last, since = vim.inspect(diag_summary(buf)), vim.uv.now()
  vim.wait(timeout, function()
    local now = vim.inspect(diag_summary(buf))
    if now ~= last then
      last, since = now, vim.uv.now()
    end
    return vim.uv.now() - since >= SETTLE_MS
  end, 50)
  return ok
end

local function hover_text(client, buf, line, word)
  local text = vim.api.nvim_buf_get_lines(buf, line - 1, line, false)[1] or ''
  local col = text:find(word, 1, true)
  if not col then
    return nil, string.format('%q not found on line %d', word, line)
  end
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    position = { line = line - 1, character = col }, -- inside the word (ASCII: UTF-16 = bytes)
  }
  local resp = client:request_sync('textDocument/hover', params, REQUEST_TIMEOUT_MS, buf)
  if not resp then
    return nil, 'hover timed out'
  end
  if resp.err then
    return nil, vim.inspect(resp.err)
  end
  local contents = resp.result and resp.result.contents
  if not contents then
    return nil, 'empty hover'
  end
  if type(contents) == 'string' then
    return contents
  end
  if contents.value then
    return contents.value
  end
  local parts = {}
  for _, c in ipairs(contents) do
    table.insert(parts, type(c) == 'string' and c or c.value)
  end
  return table.concat(parts, '\n')
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

local function hover_until(client, buf, line, word, needles)
  local text, err
  vim.wait(HOVER_TIMEOUT_MS, function()
    text, err = hover_text(client, buf, line, word)
    return contains_all(text, needles)
  end, 250)
  return text, err
end

step(function()
  local path = vim.fs.joinpath(ws, LAUNCH)
  vim.cmd.edit(vim.fn.fnameescape(path))
  local buf = vim.api.nvim_get_current_buf()
  check('launch file detected as roslaunch', vim.bo[buf].filetype == 'roslaunch', vim.bo[buf].filetype)

  -- 1. the server starts and attaches, rooted at the workspace
  local client
  vim.wait(START_TIMEOUT_MS, function()
    client = vim.lsp.get_clients({ bufnr = buf, name = 'tvl_lsp' })[1]
    return client ~= nil and client.initialized
  end, 50)
  if not check('tvl_lsp attached', client ~= nil and client.initialized) then
    return
  end
  check('root is the workspace', vim.fs.normalize(client.root_dir or '') == vim.fs.normalize(ws), client.root_dir)

  -- 2. diagnostics: every expected one, and nothing else
  local all_there = function()
    for _, e in ipairs(EXPECTED_DIAGNOSTICS) do
      local found = find_diag(buf, e.code, function(d)
        return d.lnum + 1 == e.line and (not e.contains or d.message:find(e.contains, 1, true))
      end)
      if not found then
        return false
      end
    end
    return true
  end
  local got = wait_settled(buf, DIAG_TIMEOUT_MS, all_there)
  local diags = diag_summary(buf)
  result.diagnostics = diags
  check('expected diagnostics reported', got and all_there(), diags)
  check('no other diagnostics', #diags == #EXPECTED_DIAGNOSTICS, diags)

  -- 3. hover on a feature arg and on the root arg: product counts
  -- a count may still be running when the first hover comes: the server says so and the
  -- user hovers again; so does the test, until HOVER_TIMEOUT_MS
  local text, err = hover_until(client, buf, HOVER_LINE, HOVER_WORD, HOVER_MUST_CONTAIN)
  result.hover = text or err
  check('hover on ' .. HOVER_WORD .. ' shows its product count', contains_all(text, HOVER_MUST_CONTAIN), text or err)
  text, err = hover_until(client, buf, ROOT_HOVER_LINE, ROOT_HOVER_WORD, ROOT_HOVER_MUST_CONTAIN)
  result.root_hover = text or err
  check('hover on the root ' .. ROOT_HOVER_WORD .. ' shows the total', contains_all(text, ROOT_HOVER_MUST_CONTAIN), text or err)

  -- 4. remove a feature arg (an edit in the editor: didChange), wait for missing-arg
  local lines = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
  local removed
  for i, l in ipairs(lines) do
    if l:find('<arg name="' .. REMOVE_ARG .. '"', 1, true) then
      removed = i
      break
    end
  end
  if not check('found the arg to remove', removed ~= nil, REMOVE_ARG) then
    return
  end
  vim.api.nvim_buf_set_lines(buf, removed - 1, removed, false, {})
  local missing
  vim.wait(DIAG_TIMEOUT_MS, function()
    missing = find_diag(buf, MISSING_CODE, function(d)
      return d.message:find(REMOVE_ARG, 1, true) ~= nil
    end)
    return missing ~= nil
  end, 50)
  result.diagnostics_after_removal = diag_summary(buf)
  if not check('missing-arg reported after removing ' .. REMOVE_ARG, missing ~= nil, result.diagnostics_after_removal) then
    return
  end

  -- 5. the quick fix
  local lsp_diag = missing.user_data and missing.user_data.lsp
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    range = lsp_diag.range,
    context = { diagnostics = { lsp_diag }, only = { 'quickfix' }, triggerKind = 1 }, -- as VS Code's "Quick Fix..."
  }
  local resp, req_err = client:request_sync('textDocument/codeAction', params, REQUEST_TIMEOUT_MS, buf)
  result.code_action_request = { params = params, error = req_err or (resp and resp.err) }
  local actions = resp and resp.result or {}
  local titles = {}
  local action
  for _, a in ipairs(actions) do
    table.insert(titles, a.title)
    if not action and a.title:find(REMOVE_ARG, 1, true) then
      action = a
    end
  end
  result.code_actions = titles
  if not check('a quick fix adds the arg', action ~= nil, titles) then
    return
  end
  if not action.edit and not action.command and client:supports_method('codeAction/resolve') then
    local r = client:request_sync('codeAction/resolve', action, REQUEST_TIMEOUT_MS, buf)
    action = r and r.result or action
  end
  if action.edit then
    vim.lsp.util.apply_workspace_edit(action.edit, client.offset_encoding)
  end
  if action.command then
    local cmd = type(action.command) == 'table' and action.command or action
    client:request_sync('workspace/executeCommand', { command = cmd.command, arguments = cmd.arguments }, REQUEST_TIMEOUT_MS, buf)
  end
  local after = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
  result.buffer_after = after
  local at
  for i, l in ipairs(after) do
    if l == EXPECTED_INSERTED_LINE then
      at = i
    end
  end
  check('the arg line is back, indented like the others', at ~= nil, EXPECTED_INSERTED_LINE)
  check('inserted after the last top-level arg', at ~= nil and after[at - 1] == EXPECTED_AFTER_LINE,
    at and { before = after[at - 1], line = after[at] } or nil)
  check('nothing else in the buffer changed', #after == #lines, { before = #lines, after = #after })

  -- 6. the server agrees: no missing-arg any more
  local gone = vim.wait(DIAG_TIMEOUT_MS, function()
    return find_diag(buf, MISSING_CODE) == nil
  end, 50)
  result.diagnostics_after_fix = diag_summary(buf)
  check('missing-arg gone after the fix', gone, result.diagnostics_after_fix)

  -- 7. the model: detected as tvl, attached, clean, and its root's hover gives the total
  vim.cmd.edit(vim.fn.fnameescape(vim.fs.joinpath(ws, MODEL)))
  local mbuf = vim.api.nvim_get_current_buf()
  check('model detected as tvl', vim.bo[mbuf].filetype == 'tvl', vim.bo[mbuf].filetype)
  local attached = vim.wait(START_TIMEOUT_MS, function()
    return vim.lsp.get_clients({ bufnr = mbuf, name = 'tvl_lsp' })[1] ~= nil
  end, 50)
  check('the same server attached to the model', attached and #vim.lsp.get_clients({ name = 'tvl_lsp' }) == 1)
  text, err = hover_until(client, mbuf, MODEL_HOVER_LINE, MODEL_HOVER_WORD, MODEL_HOVER_MUST_CONTAIN)
  result.model_hover = text or err
  check('hover on the model root shows the total', contains_all(text, MODEL_HOVER_MUST_CONTAIN), text or err)
  wait_settled(mbuf, DIAG_TIMEOUT_MS, function()
    return true
  end)
  result.model_diagnostics = diag_summary(mbuf)
  check('model diagnostics', #result.model_diagnostics == MODEL_EXPECTED_DIAGNOSTICS, result.model_diagnostics)

  -- 8. the configurator and the generation (the functions behind :TvlInclude, :TvlGenerate, ...)
  check(':Tvl* user commands defined', vim.fn.exists(':TvlInclude') == 2 and vim.fn.exists(':TvlGenerate') == 2)
  local tvl = require('tvl_lsp')
  local function call(fn, ...)
    local done, res, rerr = false, nil, nil
    local args = { ... }
    table.insert(args, function(r, e)
      done, res, rerr = true, r, e
    end)
    fn(unpack(args))
    vim.wait(REQUEST_TIMEOUT_MS, function()
      return done
    end, 20)
    return res, rerr
  end
  local r, e = call(tvl.include, CONFIG_FEATURE)
  result.include = r or e
  check('include ' .. CONFIG_FEATURE .. ' leaves ' .. CONFIG_REMAINING .. ' products',
    r ~= nil and tostring(r.remainingText or r.remaining) == CONFIG_REMAINING, r or e)
  r, e = call(tvl.count)
  check('count after the include', r ~= nil and tostring(r.remainingText or r.remaining) == CONFIG_REMAINING
    and tostring(r.totalText or r.total) == CONFIG_TOTAL, r or e)
  r, e = call(tvl.reset, '')
  check('reset restores every product', r ~= nil and tostring(r.remainingText or r.remaining) == CONFIG_TOTAL, r or e)
  vim.cmd.buffer(buf) -- generate from the launch file
  r, e = call(tvl.generate, GENERATE_MODE, {})
  result.generate = r or e
  local files = r and r.files or {}
  check('generated ' .. GENERATE_FILES .. ' file(s)', #files == GENERATE_FILES, r or e)
  local f = files[1] and (files[1]:match('^file://') and vim.uri_to_fname(files[1]) or files[1])
  local content = f and table.concat(vim.fn.readfile(f), '\n') or ''
  result.generated_file = { path = f, content = content }
  check('generated into ' .. GENERATE_FOLDER, f ~= nil and vim.startswith(vim.fs.normalize(f), vim.fs.joinpath(ws, GENERATE_FOLDER) .. '/'), f)
  check('generated file written with its include and args', contains_all(content, GENERATE_MUST_CONTAIN), content)
end)
