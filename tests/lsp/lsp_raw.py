"""A minimal LSP client over a server's stdio, for benchmarks and soaks (no pygls): it frames
and sends messages itself, so a test can also send bytes that are no valid message, and a
response of megabytes is timed when it arrives without being decoded."""

import asyncio
import json
import re
import time

BIG = 1 << 20  # responses larger than this are not decoded


class Client:
    """Requests are futures of (result, error); the server's own requests are answered null;
    diagnostics, log messages, other notifications (with when they arrived) and answers to no
    request of the client's (id null) are kept."""

    def __init__(self, proc):
        self.proc = proc
        self.next_id = 0
        self.pending = {}
        self.diagnostics = {}
        self.log = []
        self.unsolicited_errors = []
        self.notifications = []
        self.reader = asyncio.ensure_future(self.read())

    async def read(self):
        out = self.proc.stdout
        while True:
            length = None
            while True:
                line = await out.readline()
                if not line:
                    return
                if line in (b"\r\n", b"\n"):
                    break
                name, _, value = line.decode("ascii").partition(":")
                if name.strip().lower() == "content-length":
                    length = int(value)
            body = await out.readexactly(length)
            if len(body) > BIG and b'"method"' not in body[:40]:
                # serde_json writes `id` last: {"jsonrpc":"2.0","result":…,"id":N}
                found = re.search(rb'"id":(\d+)\}\s*$', body[-64:])
                future = self.pending.pop(int(found.group(1)), None) if found else None
                if future and not future.done():
                    future.set_result((f"<{len(body)} bytes>", None))
                continue
            message = json.loads(body)
            if "method" in message and "id" in message:  # a request of the server's
                self.send({"jsonrpc": "2.0", "id": message["id"], "result": None})
            elif "method" in message:
                params = message.get("params") or {}
                if message["method"] == "textDocument/publishDiagnostics":
                    self.diagnostics[params["uri"]] = (params.get("version"), params["diagnostics"])
                elif message["method"] in ("window/logMessage", "window/showMessage"):
                    self.log.append((params.get("type"), params.get("message", "")))
                else:  # gudsl's own (gudsl/preview, gudsl/graphChanged), with when it arrived
                    self.notifications.append((time.perf_counter(), message["method"], params))
            else:
                future = self.pending.pop(message.get("id"), None)
                if future and not future.done():
                    future.set_result((message.get("result"), message.get("error")))
                else:  # id null, or an id this client never used
                    self.unsolicited_errors.append(message.get("error"))

    def send_bytes(self, data: bytes):
        self.proc.stdin.write(data)

    def send(self, message):
        body = json.dumps(message).encode()
        self.send_bytes(b"Content-Length: %d\r\n\r\n" % len(body) + body)

    def request(self, method, params):
        self.next_id += 1
        future = asyncio.get_running_loop().create_future()
        self.pending[self.next_id] = future
        self.send({"jsonrpc": "2.0", "id": self.next_id, "method": method, "params": params})
        return future

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})


async def start_server(gudsl, root):
    """`gudsl lsp` started with `root` as its workspace, initialised, and its client."""
    proc = await asyncio.create_subprocess_exec(
        gudsl, "lsp", stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE, limit=1 << 16
    )
    client = Client(proc)
    await client.request("initialize", {"processId": None, "rootUri": root.as_uri(), "capabilities": {}})
    client.notify("initialized", {})
    return client


async def stop_server(client):
    """Shuts the server down and waits for it to exit."""
    await client.request("shutdown", None)
    client.notify("exit", None)
    await client.proc.wait()
