"""A random soak of `gudsl lsp` over the real protocol.

usage: python3 soak.py GUDSL_BINARY [MINUTES] [SEED]

Copies the sample workspace to a temporary folder and opens every file of it, each converted to
LF, CRLF, lone-CR or mixed line endings. Then, until the time is up: random edits (insertions,
deletions and replacements of identifiers, keywords, braces, line breaks of every style,
non-ASCII and astral characters, sometimes several changes in one notification), random
requests of every kind the server offers at random positions (many in flight), a document
closed and reopened now and then, and every few seconds a malformed message (not JSON, not
UTF-8, a batch, JSON-RPC 1.0, a fractional id, bytes outside any frame, a `$/` request). Every
two seconds the server's copy of every open document (`gudsl/viewFileText`) is compared with
the client's. A hostile model (issue 48) is edited among the rest: its files are set, one edit
at a time, to the server's own streams, a FIFO, links to `/dev/zero` and out of the workspace,
headers that claim exabytes, a real array; its graph is asked for over a FIFO sidecar and it is
run, with a link planted in its output folder. At the end: shutdown, exit, the exit code, and
the file that link points at, unchanged.

Prints the counts; exits 1 on a lost answer, a divergence, a panic (the server logs one when a
request panics), a malformed message left unanswered, a crash, or a write through a link."""

import asyncio
import os
import random
import shutil
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

from lsp_raw import start_server

ROOT = Path(__file__).resolve().parents[2]

PIECES = [
    "x", "Image", "width", "int", "float4", "public ", "class ", "interface ", "start ", "final ",
    "=> ", "{", "}", "(", ")", ";", ",", ".", "[", "]", " + ", " * ", "==", "\"s\"", "'c'", "0", "42",
    "1.5f", "// note", "/* c */", "é", "😀", "ß", "\t", " ", "\n", "\r\n", "\r", "\n\n", "swimlane ",
    "calc ", "return ", "if ", "ref ", "global ",
]

def frame(body: bytes) -> bytes:
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


# Each is answered with exactly one error that answers no request of the client's.
MALFORMED = [
    frame(b"{not json"),
    frame(b'{"jsonrpc":"\xff"}'),
    frame(b"[]"),
    frame(b'{"jsonrpc":"1.0","id":"m1","method":"shutdown"}'),
    frame(b'{"jsonrpc":"2.0","id":1.5,"method":"textDocument/hover"}'),
    b"garbage that is no frame at all\r\n",
    frame(b'{"jsonrpc":"2.0","id":"m2","method":"$/unknown"}'),
]


HOSTILE_PATHS = [
    "/dev/stdin", "/dev/stdout", "/dev/stderr", "/dev/zero", "fifo.npy", "zero.npy", "passwd.npy", "huge.npy",
    "overflow.npy", "../../../../../etc/passwd", "missing.npy", "depth.npy", "depth.npy",
]

HOSTILE_MODEL = """ComponentInstanceDiagram Hostile
{
    import ToF.*;
    Source instantiates DepthFile (path = "depth.npy")
    {
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Writer.In.depth ]
    }
    Writer instantiates NpyWriter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"""


def npy(descr, shape, body=b""):
    header = "{'descr': '%s', 'fortran_order': False, 'shape': %s, }" % (descr, shape)
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header.encode() + body


def plant_hostile_files(folder, victim):
    """The files a hostile repository holds beside its model; `victim` stands for a file of the
    user's that a link in the output folder points at."""
    os.mkfifo(folder / "fifo.npy")
    os.symlink("/dev/zero", folder / "zero.npy")
    os.symlink("/etc/passwd", folder / "passwd.npy")
    (folder / "huge.npy").write_bytes(npy("<f4", "(4294967296, 4294967296, 1)"))
    (folder / "overflow.npy").write_bytes(npy("<f4", "(4294967296, 4294967296, 16)"))
    (folder / "depth.npy").write_bytes(npy("<f4", "(2, 3)", bytes(24)))
    os.mkfifo(folder / "hostile.gudsl.layout")
    (folder / "hostile.gudsl").write_text(HOSTILE_MODEL)
    planted = folder / "gudsl-out" / "Hostile" / "Writer"
    planted.mkdir(parents=True)
    os.symlink(victim, planted / "distance_0000.npy")


def line_endings(text, style, rng):
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if style == "mixed":
        out = lines[0]
        for line in lines[1:]:
            out += rng.choice(["\n", "\r\n", "\r"]) + line
        return out
    return {"lf": "\n", "crlf": "\r\n", "cr": "\r"}[style].join(lines)


def position(text, offset):
    """LSP position (UTF-16) of a code-point offset; \\n, \\r\\n and \\r end lines."""
    line, start, i = 0, 0, 0
    while i < offset:
        c = text[i]
        if c == "\r" and i + 1 < len(text) and text[i + 1] == "\n":
            if i + 1 >= offset:
                break
            i += 2
            line, start = line + 1, i
            continue
        if c in "\r\n":
            line, start = line + 1, i + 1
        i += 1
    return {"line": line, "character": len(text[start:offset].encode("utf-16-le")) // 2}


def safe_offset(text, offset):
    """Never between the \\r and \\n of one line break."""
    if 0 < offset < len(text) and text[offset - 1] == "\r" and text[offset] == "\n":
        return offset - 1
    return offset


async def main(gudsl, minutes, seed):
    rng = random.Random(seed)
    root = Path(tempfile.mkdtemp(prefix="gudsl-soak-"))
    shutil.copytree(ROOT / "samples", root / "samples", ignore=shutil.ignore_patterns("rendered"))
    victim = root / "victim"
    victim.write_text("the user's own file\n")
    plant_hostile_files(root / "samples", victim)
    paths = sorted((root / "samples").rglob("*.gudsl"))
    hostile = (root / "samples" / "hostile.gudsl").as_uri()
    client = await start_server(gudsl, root)
    proc = client.proc

    docs = {}  # uri -> [text, version]
    styles = Counter()

    def open_doc(path):
        style = rng.choice(["lf", "crlf", "cr", "mixed"])
        styles[style] += 1
        text = line_endings(path.read_text(), style, rng)
        uri = path.as_uri()
        docs[uri] = [text, 1]
        client.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}})

    for path in paths:
        open_doc(path)

    counts = Counter()
    outstanding = set()
    errors = Counter()

    def track(future, kind):
        counts["requests sent"] += 1
        outstanding.add(future)

        def done(f):
            outstanding.discard(f)
            counts["requests answered"] += 1
            _, error = f.result()
            if error:
                errors[(kind, error.get("code"))] += 1

        future.add_done_callback(done)

    def random_position(uri):
        text = docs[uri][0]
        return position(text, safe_offset(text, rng.randint(0, len(text))))

    def random_request(uri):
        kind = rng.choice([
            "hover", "completion", "definition", "typeDefinition", "references", "documentHighlight",
            "documentSymbol", "semanticTokens/full", "foldingRange", "selectionRange", "codeAction",
            "inlayHint", "signatureHelp", "formatting", "prepareRename", "rename", "workspace/symbol",
        ])
        doc = {"textDocument": {"uri": uri}}
        at = {**doc, "position": random_position(uri)}
        a, b = sorted([random_position(uri), random_position(uri)], key=lambda p: (p["line"], p["character"]))
        params = {
            "references": {**at, "context": {"includeDeclaration": rng.random() < 0.5}},
            "documentSymbol": doc, "semanticTokens/full": doc, "foldingRange": doc,
            "selectionRange": {**doc, "positions": [random_position(uri), random_position(uri)]},
            "codeAction": {**doc, "range": {"start": a, "end": b}, "context": {"diagnostics": []}},
            "inlayHint": {**doc, "range": {"start": a, "end": b}},
            "formatting": {**doc, "options": {"tabSize": 4, "insertSpaces": True}},
            "rename": {**at, "newName": rng.choice(["Renamed", "x1", "bad name", ""])},
            "workspace/symbol": {"query": rng.choice(["", "Image", "a", "Filter"])},
        }.get(kind, at)
        method = kind if kind.startswith("workspace/") else f"textDocument/{kind}"
        track(client.request(method, params), kind)

    def hostile_edit(uri):
        """The hostile model's file set to another hostile path."""
        text, version = docs[uri]
        start = text.index('path = "') + len('path = "')
        end = text.index('"', start)
        new = rng.choice(HOSTILE_PATHS)
        change = {"range": {"start": position(text, start), "end": position(text, end)}, "text": new}
        docs[uri] = [text[:start] + new + text[end:], version + 1]
        client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version + 1}, "contentChanges": [change]})
        counts["hostile edits"] += 1

    def hostile_request(uri):
        if rng.random() < 0.5:
            track(client.request("gudsl/graph", {"textDocument": {"uri": uri}, "diagram": "Hostile"}), "gudsl/graph")
        else:
            run = {"command": "gudsl.runPipeline", "arguments": [{"diagram": "Hostile", "cpu": True}]}
            track(client.request("workspace/executeCommand", run), "runPipeline")

    def random_edit(uri):
        if uri == hostile:
            return hostile_edit(uri)
        text, version = docs[uri]
        changes = []
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            start = safe_offset(text, rng.randint(0, len(text)))
            end = safe_offset(text, min(len(text), start + rng.choice([0, 0, 1, 2, 5, 20])))
            new = "".join(rng.choice(PIECES) for _ in range(rng.choice([0, 1, 1, 2, 3])))
            changes.append({"range": {"start": position(text, start), "end": position(text, end)}, "text": new})
            text = text[:start] + new + text[end:]
        version += 1
        docs[uri] = [text, version]
        client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": changes})
        counts["edits"] += len(changes)

    async def compare_texts():
        for uri, (text, _) in list(docs.items()):
            server_text, error = await client.request("gudsl/viewFileText", {"uri": uri})
            counts["text checks"] += 1
            if error or server_text != text:
                counts["divergences"] += 1
                print(f"DIVERGENCE in {uri}: {error or ''}", file=sys.stderr)
                docs[uri][0] = server_text if isinstance(server_text, str) else text

    start = time.monotonic()
    deadline = start + minutes * 60
    next_check = start + 2
    next_malformed = start + rng.uniform(2, 5)
    while time.monotonic() < deadline and proc.returncode is None:
        uri = rng.choice(list(docs))
        roll = rng.random()
        if roll < 0.55:
            random_edit(uri)
        elif uri == hostile and roll < 0.65:
            hostile_request(uri)
        elif roll < 0.995:
            random_request(uri)
        else:
            client.notify("textDocument/didClose", {"textDocument": {"uri": uri}})
            counts["closed and reopened"] += 1
            open_doc(Path(uri.removeprefix("file://")))
        now = time.monotonic()
        if now >= next_malformed:
            client.send_bytes(rng.choice(MALFORMED))
            counts["malformed messages"] += 1
            next_malformed = now + rng.uniform(2, 5)
        if now >= next_check:
            await compare_texts()
            next_check = time.monotonic() + 2
        if len(outstanding) > 64:
            await asyncio.wait(list(outstanding), timeout=30)
        await proc.stdin.drain()
        await asyncio.sleep(0)

    crashed = proc.returncode is not None
    if not crashed:
        await compare_texts()
        if outstanding:
            await asyncio.wait(list(outstanding), timeout=60)
        _, error = await asyncio.wait_for(client.request("shutdown", None), 60)
        client.notify("exit", None)
        code = await asyncio.wait_for(proc.wait(), 30)
    else:
        code = proc.returncode
    panics = sum(1 for _, message in client.log if "panicked" in message)
    lost = len(outstanding)
    unanswered_malformed = counts["malformed messages"] - len(client.unsolicited_errors)
    elapsed = (time.monotonic() - start) / 60
    print(f"soak of {elapsed:.1f} minutes, seed {seed}, {len(paths)} documents (line endings {dict(styles)})")
    overwritten = victim.read_text() != "the user's own file\n"
    for name in ["edits", "hostile edits", "requests sent", "requests answered", "text checks", "divergences", "malformed messages",
                 "closed and reopened"]:
        print(f"  {name:<24} {counts[name]}")
    by_code = Counter((e or {}).get("code") for e in client.unsolicited_errors)
    print(f"  {'answers to malformed':<24} {len(client.unsolicited_errors)} (by code: {dict(by_code)})")
    print(f"  {'lost answers':<24} {lost}")
    print(f"  {'panics logged':<24} {panics}")
    print(f"  {'crashed':<24} {crashed}")
    print(f"  {'written through a link':<24} {overwritten}")
    print(f"  {'exit code':<24} {code}")
    print("  request errors by kind and code: " + ", ".join(f"{k}/{c}: {n}" for (k, c), n in sorted(errors.items(), key=str)))
    failed = crashed or lost or panics or counts["divergences"] or code != 0 or unanswered_malformed != 0 or overwritten
    return 1 if failed else 0


if __name__ == "__main__":
    minutes = float(sys.argv[2]) if len(sys.argv) > 2 else 30
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    sys.exit(asyncio.run(main(sys.argv[1], minutes, seed)))
