-- Headless Neovim with editors/neovim/gudsl.lua, as a user's config: opens a sample, waits for
-- `gudsl lsp` to attach, breaks the text and sees the diagnostic, then fixes it and sees it go;
-- hover, go to definition, completion after `=> `, rename's edits, and gudsl's own
-- `gudsl/diagrams`. Prints `ok …` per check; exits 1 on the first failure (`:cquit`).
local TIMEOUT = 20000
local results = {}
local function ok(name, extra)
  table.insert(results, name)
  io.stdout:write(string.format('ok   %s %s\n', name, extra or ''))
end
local function fail(why)
  io.stdout:write('FAIL ' .. why .. '\n')
  vim.cmd('cquit 1')
end
local function wait(what, test)
  if not vim.wait(TIMEOUT, test, 50) then
    fail('timed out waiting for ' .. what)
  end
end

local buf = vim.api.nvim_get_current_buf()
if vim.bo[buf].filetype ~= 'gudsl' then
  fail('filetype is "' .. vim.bo[buf].filetype .. '", not gudsl')
end
wait('the client to attach', function()
  return #vim.lsp.buf_get_clients(buf) > 0 and vim.lsp.buf_get_clients(buf)[1 + 0] ~= nil
end)
local client
for _, c in pairs(vim.lsp.buf_get_clients(buf)) do
  client = c
end
wait('initialize', function()
  return client.initialized or client.server_capabilities ~= nil
end)
ok('gudsl lsp attached', client.name)

local function find_line(text)
  for i, line in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    if line:find(text, 1, true) then
      return i - 1, line
    end
  end
  fail('no line with ' .. text)
end

-- A transition to a node that does not exist: E0204 appears, and goes when the line is removed.
local row = find_line('=> guardedAction;')
vim.api.nvim_buf_set_lines(buf, row + 1, row + 1, false, { '        => missingNode;' })
wait('E0204', function()
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if d.code == 'E0204' or (d.message or ''):find('missingNode', 1, true) then
      return true
    end
  end
  return false
end)
ok('diagnostic appears', vim.diagnostic.get(buf)[1].message)
vim.api.nvim_buf_set_lines(buf, row + 1, row + 2, false, {})
wait('the diagnostic to clear', function()
  return #vim.diagnostic.get(buf, { severity = vim.diagnostic.severity.ERROR }) == 0
end)
ok('diagnostic clears')

local function request(method, params)
  local answers, err = vim.lsp.buf_request_sync(buf, method, params, TIMEOUT)
  if not answers then
    fail(method .. ': ' .. tostring(err))
  end
  for _, answer in pairs(answers) do
    if answer.err then
      fail(method .. ': ' .. vim.inspect(answer.err))
    end
    return answer.result
  end
end
local function at(line, text)
  local col = vim.api.nvim_buf_get_lines(buf, line, line + 1, false)[1]:find(text, 1, true) - 1
  return { textDocument = vim.lsp.util.make_text_document_params(buf), position = { line = line, character = col } }
end

-- Hover and definition on the `guardedAction` of `=> guardedAction;`.
local hover = request('textDocument/hover', at(row, 'guardedAction'))
if not (hover and vim.inspect(hover.contents):find('guardedAction', 1, true)) then
  fail('hover: ' .. vim.inspect(hover))
end
ok('hover')
local definition = request('textDocument/definition', at(row, 'guardedAction'))
local location = definition[1] or definition
local declared = find_line('action guardedAction')
if (location.range or location.targetSelectionRange).start.line ~= declared then
  fail('definition: ' .. vim.inspect(definition))
end
ok('go to definition', 'line ' .. declared + 1)

-- Completion after `=> ` lists the diagram's nodes.
vim.api.nvim_buf_set_lines(buf, row + 1, row + 1, false, { '        => ' })
local completion = request('textDocument/completion', { textDocument = vim.lsp.util.make_text_document_params(buf), position = { line = row + 1, character = 11 } })
local labels = {}
for _, item in ipairs(completion.items or completion) do
  labels[item.label] = true
end
if not labels['nonguardedAction'] then
  fail('completion: ' .. vim.inspect(vim.tbl_keys(labels)))
end
ok('completion after "=> "', table.concat(vim.tbl_keys(labels), ' '))
vim.api.nvim_buf_set_lines(buf, row + 1, row + 2, false, {})

-- Rename answers the edits for the declaration and every use.
local rename = request('textDocument/rename', vim.tbl_extend('force', at(declared, 'guardedAction'), { newName = 'checkedAction' }))
local count = 0
for _, edits in pairs(rename.changes or {}) do
  count = count + #edits
end
for _, change in ipairs(rename.documentChanges or {}) do
  count = count + #(change.edits or {})
end
if count < 2 then
  fail('rename: ' .. vim.inspect(rename))
end
ok('rename', count .. ' edits')

-- gudsl's own request, as :GudslDiagrams sends it.
local diagrams = request('gudsl/diagrams', { textDocument = vim.lsp.util.make_text_document_params(buf) })
if not (diagrams and diagrams.diagrams[1] and diagrams.diagrams[1].id == 'TransitionExample') then
  fail('gudsl/diagrams: ' .. vim.inspect(diagrams))
end
ok('gudsl/diagrams', diagrams.diagrams[1].id)

io.stdout:write(#results .. ' passed\n')
vim.cmd('qall!')
