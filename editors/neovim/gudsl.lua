-- GU-DSL in Neovim (0.7 or newer): the `.gudsl` filetype and `gudsl lsp` for it.
--
--   Put this file on your runtimepath (e.g. ~/.config/nvim/lua/gudsl.lua) and call
--     require('gudsl').setup()                     -- `gudsl` on PATH
--     require('gudsl').setup({ cmd = { '/path/to/gudsl', 'lsp' } })
--   or source it from init.lua: `dofile('/path/to/editors/neovim/gudsl.lua').setup()`.
--
-- Diagnostics, hover, go to definition, references, rename, completion, formatting, code actions
-- and semantic highlighting come through Neovim's built-in client; `:GudslDiagrams` lists the
-- current file's diagrams through gudsl's own `gudsl/diagrams` request.
local M = {}

local function root_of(path)
  local markers = { '.git', 'Cargo.toml' }
  local dir = vim.fn.fnamemodify(path, ':p:h')
  while dir and dir ~= '' do
    for _, marker in ipairs(markers) do
      if vim.loop.fs_stat(dir .. '/' .. marker) then
        return dir
      end
    end
    local parent = vim.fn.fnamemodify(dir, ':h')
    if parent == dir then
      break
    end
    dir = parent
  end
  return vim.fn.fnamemodify(path, ':p:h')
end

local clients = {}

--- Starts (or reuses) the server for the buffer's project and attaches it.
local function attach(bufnr, opts)
  local root = root_of(vim.api.nvim_buf_get_name(bufnr))
  if vim.lsp.start then -- 0.8 and newer: reuses a client of the same name and root
    vim.lsp.start({ name = 'gudsl', cmd = opts.cmd, root_dir = root, on_attach = opts.on_attach }, { bufnr = bufnr })
    return
  end
  local id = clients[root]
  if not id or vim.lsp.get_client_by_id(id) == nil then
    id = vim.lsp.start_client({
      name = 'gudsl',
      cmd = opts.cmd,
      root_dir = root,
      workspace_folders = { { uri = vim.uri_from_fname(root), name = vim.fn.fnamemodify(root, ':t') } },
      on_attach = opts.on_attach,
    })
    clients[root] = id
  end
  if id then
    vim.lsp.buf_attach_client(bufnr, id)
  end
end

function M.setup(opts)
  opts = vim.tbl_extend('force', { cmd = { 'gudsl', 'lsp' } }, opts or {})
  if vim.filetype and vim.filetype.add then
    vim.filetype.add({ extension = { gudsl = 'gudsl' } })
  end
  -- Neovim 0.7 detects filetypes with filetype.vim unless told otherwise.
  local group = vim.api.nvim_create_augroup('gudsl', { clear = true }) -- setup() twice: once
  vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, { group = group, pattern = '*.gudsl', command = 'setfiletype gudsl' })
  vim.api.nvim_create_autocmd('FileType', {
    group = group,
    pattern = 'gudsl',
    callback = function(args)
      vim.bo[args.buf].commentstring = '// %s'
      attach(args.buf, opts)
    end,
  })
  vim.api.nvim_create_user_command('GudslDiagrams', function()
    local params = { textDocument = vim.lsp.util.make_text_document_params() }
    vim.lsp.buf_request(0, 'gudsl/diagrams', params, function(err, result)
      if err then
        vim.notify('gudsl/diagrams: ' .. err.message, vim.log.levels.ERROR)
        return
      end
      local lines = {}
      for _, d in ipairs((result or {}).diagrams or {}) do
        table.insert(lines, string.format('%s (%s diagram) line %d', d.id, d.kind, d.selectionRange.start.line + 1))
      end
      vim.notify(#lines > 0 and table.concat(lines, '\n') or 'no diagrams')
    end)
  end, {})
end

return M
