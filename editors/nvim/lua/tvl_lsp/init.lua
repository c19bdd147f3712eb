-- Neovim front end for tvl-lsp's commands: the configurator and the generation of
-- configuration launch files. Each function works on the current buffer (a TVL model or a
-- launch file paired with one) and calls `on_result(result, err)` (default: a notification).
local M = {}

local function client_for(bufnr)
  local c = vim.lsp.get_clients({ bufnr = bufnr, name = 'tvl_lsp' })[1]
  if not c then
    vim.notify('tvl-lsp is not attached to this buffer', vim.log.levels.ERROR)
  end
  return c
end

--- Run a server command (workspace/executeCommand) and pass its result to on_result.
function M.exec(command, arguments, on_result, bufnr)
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  local client = client_for(bufnr)
  if not client then
    return
  end
  client:request('workspace/executeCommand', { command = command, arguments = arguments }, function(err, result)
    if err then
      vim.notify(string.format('%s: %s', command, err.message or vim.inspect(err)), vim.log.levels.ERROR)
    end
    if on_result then
      on_result(result, err)
    end
  end, bufnr)
end

local function remaining_text(r)
  if not r then
    return '?'
  end
  local rem = r.remainingText or (r.remaining ~= nil and r.remaining ~= vim.NIL and tostring(r.remaining)) or '?'
  local tot = r.totalText or (r.total ~= nil and r.total ~= vim.NIL and tostring(r.total)) or nil
  if tot and tot ~= vim.NIL then
    return string.format('%s of %s products', rem, tot)
  end
  return rem .. ' products'
end

local function notify_remaining(what)
  return function(r, err)
    if not err and r then
      local msg = string.format('%s: %s remain', what, remaining_text(r))
      if type(r.forced) == 'table' and next(r.forced) then
        local f = {}
        for name, on in pairs(r.forced) do
          table.insert(f, on and name or ('!' .. name))
        end
        table.sort(f)
        msg = msg .. '; forced: ' .. table.concat(f, ', ')
      end
      vim.notify(msg)
    end
  end
end

local function uri()
  return vim.uri_from_bufnr(vim.api.nvim_get_current_buf())
end

function M.include(feature, on_result)
  feature = feature ~= '' and feature or vim.fn.expand('<cword>')
  M.exec('tvl-lsp.include', { uri(), feature }, on_result or notify_remaining('included ' .. feature))
end

function M.exclude(feature, on_result)
  feature = feature ~= '' and feature or vim.fn.expand('<cword>')
  M.exec('tvl-lsp.exclude', { uri(), feature }, on_result or notify_remaining('excluded ' .. feature))
end

function M.reset(feature, on_result)
  local args = { uri() }
  if feature and feature ~= '' then
    table.insert(args, feature)
  end
  M.exec('tvl-lsp.reset', args, on_result or notify_remaining('reset'))
end

function M.count(on_result)
  M.exec('tvl-lsp.count', { uri() }, on_result or notify_remaining('count'))
end

function M.list_products(limit, on_result)
  M.exec('tvl-lsp.listProducts', { uri(), limit or 100 }, on_result or function(r)
    if not r or not r.products then
      return
    end
    local lines = {}
    for i, p in ipairs(r.products) do
      table.insert(lines, string.format('%d: %s', i, table.concat(p, ', ')))
    end
    if r.truncated then
      table.insert(lines, '…')
    end
    vim.notify(table.concat(lines, '\n'))
  end)
end

--- Generate configuration launch files (mode: 'one' | 'completions' | 'all'). The server
--- creates them through workspace/applyEdit; the new buffers are written to disk here.
function M.generate(mode, opts, on_result)
  opts = opts or {}
  local args = vim.tbl_extend('force', { uri = uri(), mode = mode ~= '' and mode or 'all' }, opts)
  M.exec('tvl-lsp.generateConfigurations', { args }, function(r, err)
    if not err and r and type(r.files) == 'table' then
      for _, f in ipairs(r.files) do
        local path = f:match('^file://') and vim.uri_to_fname(f) or f
        local b = vim.fn.bufnr(path)
        if b ~= -1 and vim.bo[b].modified then
          vim.api.nvim_buf_call(b, function()
            vim.cmd('silent noautocmd write')
          end)
        end
      end
      if not on_result then
        vim.notify(string.format('generated %d configuration launch file(s)%s', #r.files, r.truncated and ' (limit reached)' or ''))
      end
    end
    if on_result then
      on_result(r, err)
    end
  end)
end

return M
