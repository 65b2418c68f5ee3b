"""Slow requests against `gudsl lsp` over the real protocol.

usage: python3 slow_requests.py GUDSL_BINARY [ROUNDS [ONLY]]   (ONLY: run the hover phase only
                                                                 for slow kinds naming it)

Builds a workspace of 4 000 types, then measures
  1. single requests that used to be slow: a code action on a 20 000-character unknown type
     name; semantic tokens and document symbols of a 369 KB document on one line and of the
     same with line breaks; opening a 10 MB document (time to its diagnostics, the server's
     peak memory); semantic tokens and symbols of the 10 MB document;
  2. a hover on file A, each right after an edit of A, while file B has a slow request running
     (re-sent as soon as it is answered or cancelled): p50/p95 per kind of slow request.
Prints a table; exits 1 if a hover's p95 is 50 ms or more.

The client speaks the protocol itself (no pygls): a response of megabytes is timed when its
last byte arrives and is not decoded, so what is measured is the server, not the client's
JSON decoding (pygls needs ~30 s to structure the 500 000 symbols of the 10 MB document, and
cannot read a hover's answer meanwhile)."""

import asyncio
import sys
import tempfile
import time
from pathlib import Path

from lsp_raw import start_server, stop_server


def pct(samples):
    xs = sorted(samples)
    q = lambda p: xs[min(len(xs) - 1, int(round(p * (len(xs) - 1))))]
    return q(0.5) * 1e3, q(0.95) * 1e3, len(xs)


def proc_status(pid, key):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1]) / 1024
    return float("nan")


def types_workspace(root: Path):
    """4 000 classes in 40 files, and file A: a class using them and an activity."""
    for f in range(40):
        classes = "\n".join(f"    public class T{f}x{c} {{ public int v{c}; }}" for c in range(100))
        (root / f"types{f:02}.gudsl").write_text(f"ClassDiagram Types{f:02}\n{{\n{classes}\n}}\n")
    (root / "a.gudsl").write_text(
        "ClassDiagram A\n{\n    public class Holder\n    {\n        public T0x1 first;\n"
        "        public int count;\n        public void touch(int n)\n        {\n            count = n;\n        }\n    }\n}\n"
    )


def one_line_document(kib, name):
    """A class diagram of `kib` KiB with no line break, and the same with one per class."""
    parts = []
    size = 0
    i = 0
    while size < kib * 1024:
        part = f"public class L{i} {{ public int f{i}; public T0x{i % 100} g{i}; }} "
        parts.append(part)
        size += len(part)
        i += 1
    return f"ClassDiagram {name} {{ " + "".join(parts) + "}", f"ClassDiagram {name}Lines {{\n" + "\n".join(parts) + "\n}\n"


def doc(uri):
    return {"textDocument": {"uri": uri}}


async def main(gudsl, rounds):
    root = Path(tempfile.mkdtemp(prefix="gudsl-slow-"))
    types_workspace(root)
    client = await start_server(gudsl, root)
    a_uri = (root / "a.gudsl").as_uri()

    async def wait_diagnostics(uri, timeout=300):
        start = time.perf_counter()
        while uri not in client.diagnostics:
            await asyncio.sleep(0.005)
            if time.perf_counter() - start > timeout:
                raise SystemExit(f"no diagnostics for {uri}")
        return client.diagnostics[uri]

    await wait_diagnostics(a_uri, 120)

    def open_doc(name, text):
        uri = (root / name).as_uri()
        client.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}})
        return uri

    rows = []

    async def timed(name, make):
        start = time.perf_counter()
        result, error = await make()
        outcome = "answered" if error is None else f"error {error['code']}"
        rows.append((name, (time.perf_counter() - start) * 1e3, outcome, proc_status(client.proc.pid, "VmHWM")))

    # 1. Single requests.
    long_name = "Unknown" + "x" * 20_000
    b1 = open_doc("b1.gudsl", f"ClassDiagram B1\n{{\n    public class C {{ public {long_name} m; }}\n}}\n")
    _, found = await wait_diagnostics(b1)
    where = next(d for d in found if d["code"] == "E0201")["range"]
    code_action = lambda: client.request(
        "textDocument/codeAction", {**doc(b1), "range": where, "context": {"diagnostics": []}}
    )
    await timed("code action, 20 000-char unknown name, 4 000 types", code_action)
    one_line, broken = one_line_document(369, "OneLine")
    for name, text in [("369 KB on one line", one_line), ("369 KB, a line per class", broken)]:
        uri = open_doc(f"b2-{len(text.splitlines())}.gudsl", text)
        await wait_diagnostics(uri)
        await timed(f"semantic tokens, {name}", lambda: client.request("textDocument/semanticTokens/full", doc(uri)))
        await timed(f"document symbols, {name}", lambda: client.request("textDocument/documentSymbol", doc(uri)))
    rss_before = proc_status(client.proc.pid, "VmRSS")
    _, huge = one_line_document(10 * 1024, "Huge")
    start = time.perf_counter()
    b3 = open_doc("b3.gudsl", huge)
    await wait_diagnostics(b3)
    rows.append(("open 10 MB document -> its diagnostics", (time.perf_counter() - start) * 1e3, "answered", proc_status(client.proc.pid, "VmHWM")))
    semantic_tokens = lambda: client.request("textDocument/semanticTokens/full", doc(b3))
    document_symbols = lambda: client.request("textDocument/documentSymbol", doc(b3))
    await timed("semantic tokens, 10 MB document", semantic_tokens)
    await timed("document symbols, 10 MB document", document_symbols)

    print(f"{'single request':<56} {'ms':>9} {'peak MiB':>9}  outcome")
    for name, ms, outcome, peak in rows:
        print(f"{name:<56} {ms:>9.1f} {peak:>9.0f}  {outcome}")
    print(f"server memory: {rss_before:.0f} MiB before the 10 MB document")

    # 2. Hovers on A while B has a slow request running.
    a_text = (root / "a.gudsl").read_text()
    lines = a_text.splitlines()
    client.notify("textDocument/didOpen", {"textDocument": {"uri": a_uri, "languageId": "gudsl", "version": 1, "text": a_text}})
    hover_at = {"line": 4, "character": lines[4].index("T0x1") + 1}
    body_at = {"line": 8, "character": lines[8].index("n;")}
    slow_kinds = [
        ("nothing (the control)", None),
        ("semantic tokens of a 10 MB document", semantic_tokens),
        ("document symbols of a 10 MB document", document_symbols),
        ("code action, 20 000-char name", code_action),
    ]
    version = 1
    failed = False
    print(f"\n{'hover on A after an edit of A, while B runs':<56} {'p50 ms':>8} {'p95 ms':>8} {'n':>5} {'slow answered/cancelled':>24}")
    only = sys.argv[3] if len(sys.argv) > 3 else ""
    for kind, make in [(kind, make) for kind, make in slow_kinds if only in kind]:
        stop = asyncio.Event()
        counts = {"answered": 0, "cancelled": 0}

        async def keep_busy():
            while make and not stop.is_set():
                _, error = await make()
                counts["answered" if error is None else "cancelled"] += 1

        busy = asyncio.ensure_future(keep_busy())
        await asyncio.sleep(0.5)
        hovers = []
        for k in range(rounds):
            version += 1
            end = body_at if k % 2 == 0 else {**body_at, "character": body_at["character"] + 1}
            client.notify(
                "textDocument/didChange",
                {
                    "textDocument": {"uri": a_uri, "version": version},
                    "contentChanges": [{"range": {"start": body_at, "end": end}, "text": "1" if k % 2 == 0 else ""}],
                },
            )
            start = time.perf_counter()
            answer, error = await client.request("textDocument/hover", {**doc(a_uri), "position": hover_at})
            hovers.append(time.perf_counter() - start)
            assert error is None and "T0x1" in answer["contents"]["value"], (answer, error)
            await asyncio.sleep(0.05)
        stop.set()
        await busy
        p50, p95, n = pct(hovers)
        failed |= p95 >= 50
        print(f"{kind:<56} {p50:>8.2f} {p95:>8.2f} {n:>5} {counts['answered']:>12}/{counts['cancelled']:<11}")

    await stop_server(client)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(asyncio.run(main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 100)))
