"""What the pygls-driven end-to-end tests share: failing with a message, and waiting for what the
server sends (diagnostics, progress) with a deadline."""

import asyncio
import sys


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


async def wait_for(predicate, what, timeout=10.0):
    """The first truthy value of `predicate()`, polled until `timeout` seconds have passed."""
    deadline = asyncio.get_running_loop().time() + timeout
    while asyncio.get_running_loop().time() < deadline:
        value = predicate()
        if value:
            return value
        await asyncio.sleep(0.02)
    fail(f"timed out waiting for {what}")


def field(value, name):
    """A field of a value pygls gives as an object or as a dict."""
    return getattr(value, name, None) if not isinstance(value, dict) else value.get(name)


async def refused(request, what):
    """The JSON-RPC error a request is answered with; fails when it is answered with a result."""
    from pygls.exceptions import JsonRpcException

    try:
        result = await request
    except JsonRpcException as error:
        return error
    fail(f"{what} was not refused: {result}")


class Seen:
    """What the server sent a client: its capabilities, diagnostics (and their version) by URI, progress values by
    token, the progress tokens it created, log messages, shown messages (type, text) and `gudsl/graphChanged`
    notifications."""

    def __init__(self):
        self.diagnostics, self.progress, self.created, self.logs, self.shown = {}, {}, [], [], []
        self.diagnostics_version = {}
        self.graph_changed = []
        self.capabilities = None


async def start_client(name, gudsl, root):
    """`gudsl lsp` started and initialised with `root` as its workspace folder, by a client that
    accepts work-done progress and records what the server sends."""
    from lsprotocol import types as t
    from pygls.lsp.client import LanguageClient

    client, seen = LanguageClient(name, "1.0"), Seen()

    @client.feature(t.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params):
        seen.diagnostics[params.uri] = params.diagnostics
        seen.diagnostics_version[params.uri] = params.version

    @client.feature(t.WINDOW_WORK_DONE_PROGRESS_CREATE)
    def on_progress_create(params):
        seen.created.append(str(params.token))

    @client.feature(t.CLIENT_REGISTER_CAPABILITY)
    def on_register(params):
        return None

    @client.feature(t.PROGRESS)
    def on_progress(params):
        seen.progress.setdefault(str(params.token), []).append(params.value)

    @client.feature(t.WINDOW_LOG_MESSAGE)
    def on_log(params):
        seen.logs.append(params.message)

    @client.feature(t.WINDOW_SHOW_MESSAGE)
    def on_show(params):
        seen.shown.append((params.type, params.message))

    @client.feature("gudsl/graphChanged")
    def on_graph_changed(params):
        seen.graph_changed.append(params)

    await client.start_io(gudsl, "lsp")
    seen.capabilities = await client.initialize_async(
        t.InitializeParams(
            process_id=None,
            root_uri=root.as_uri(),
            workspace_folders=[t.WorkspaceFolder(uri=root.as_uri(), name=root.name)],
            capabilities=t.ClientCapabilities(window=t.WindowClientCapabilities(work_done_progress=True)),
        )
    )
    seen.capabilities = seen.capabilities.capabilities
    client.initialized(t.InitializedParams())
    return client, seen
