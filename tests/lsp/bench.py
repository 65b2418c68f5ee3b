"""LSP latency benchmarks of `gudsl lsp` over the real protocol, in two workload shapes.

body: python3 bench.py body GUDSL_BINARY WORKSPACE_DIR [KEYSTROKES]

  Loads the workspace (e.g. `cargo run --release -p gudsl-model --example synth -- DIR`: 200
  files, 50 000 lines), opens pkg100.gudsl, replays typing (insertions and deletions inside a
  method body and inside a declaration), and measures keystroke -> publishDiagnostics of that
  version, and round trips of completion, hover and references while typing (pygls client).

linked: python3 bench.py linked --gudsl BIN --workspace DIR [--langium CMD --langium-workspace DIR]
                                [--runs N] [--out FILE.json]

  The workspace-scale scenario of issue 14, the shape of the Langium anchor in
  `research/lsp-anchors/` (generate ours with `cargo run --release -p gudsl-model --example
  synth -- --linked DIR 200`, the anchor's with its `gen_workspace.py dmodel DIR 200`): every
  file opened; 200 keystrokes in f001 in blocks of four — a character into a field's type (the
  type becomes unknown), a character appended to a class name used in the same file and others,
  then both deleted; 100 idle completions, hovers, definitions and references. Runs gudsl and,
  given `--langium`, the anchor on its own workload alternately (N runs each) with one client,
  and prints the medians side by side. A keystroke's latency is the time from sending didChange
  to the first publishDiagnostics of the edited file whose content is the expected one (the set
  of unresolved names), as the anchor measures it (Langium sends no version); for gudsl that
  publish must also carry the version just sent.
"""

import asyncio
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types as t
from pygls.lsp.client import LanguageClient


def pct(samples):
    xs = sorted(samples)
    q = lambda p: xs[min(len(xs) - 1, int(round(p * (len(xs) - 1))))]
    return q(0.5) * 1e3, q(0.95) * 1e3, len(xs)


def rss_mib(pid):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


async def main(gudsl, root, keystrokes):
    root = Path(root).resolve()
    files = sorted(root.glob("*.gudsl"))
    target = root / "pkg100.gudsl"
    text = target.read_text()
    uri = target.as_uri()
    client = LanguageClient("gudsl-bench", "1.0")
    arrivals = {}
    loaded = asyncio.Event()
    seen = set()

    @client.feature(t.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params):
        arrivals[(params.uri, params.version)] = time.perf_counter()
        seen.add(params.uri)
        if len(seen) >= len(files):
            loaded.set()

    @client.feature(t.CLIENT_REGISTER_CAPABILITY)
    def on_register(params):
        return None

    @client.feature(t.WINDOW_WORK_DONE_PROGRESS_CREATE)
    def on_create(params):
        return None

    @client.feature(t.PROGRESS)
    def on_progress(params):
        return None

    start = time.perf_counter()
    await client.start_io(gudsl, "lsp")
    pid = client._server.pid
    await client.initialize_async(
        t.InitializeParams(
            process_id=None,
            root_uri=root.as_uri(),
            workspace_folders=[t.WorkspaceFolder(uri=root.as_uri(), name="ws")],
            capabilities=t.ClientCapabilities(
                general=t.GeneralClientCapabilities(position_encodings=[t.PositionEncodingKind.Utf16]),
                window=t.WindowClientCapabilities(work_done_progress=True),
            ),
        )
    )
    client.initialized(t.InitializedParams())
    await asyncio.wait_for(loaded.wait(), 120)
    cold = time.perf_counter() - start
    rss_loaded = rss_mib(pid)

    client.text_document_did_open(
        t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=uri, language_id="gudsl", version=1, text=text))
    )
    lines = text.splitlines()
    body_line = next(i for i, l in enumerate(lines) if "var int acc = a * " in l)
    body_col = lines[body_line].index("var int acc = a * ") + len("var int acc = a * ")
    decl_line = next(i for i, l in enumerate(lines) if l.strip().startswith("public") and " field0;" in l)
    decl_col = lines[decl_line].index(" field0;") + len(" field0")
    transition_line = next(i for i, l in enumerate(lines) if l.strip().startswith("=> step0;"))
    hover_line = next(i for i, l in enumerate(lines) if "owner Pkg100.Image100" in l)
    hover_col = lines[hover_line].index("Image100") + 2

    diag, completion, hover, references = [], [], [], []
    version = 1
    doc = t.TextDocumentIdentifier(uri=uri)
    for k in range(keystrokes):
        version += 1
        # Alternate: type then delete a digit in a method body; every 10th keystroke, type then
        # delete a character in a field's name (a declaration change).
        in_decl = (k // 2) % 10 == 9
        line, col = (decl_line, decl_col) if in_decl else (body_line, body_col)
        if k % 2 == 0:
            change = t.TextDocumentContentChangePartial(
                range=t.Range(start=t.Position(line=line, character=col), end=t.Position(line=line, character=col)), text="1"
            )
        else:
            change = t.TextDocumentContentChangePartial(
                range=t.Range(start=t.Position(line=line, character=col), end=t.Position(line=line, character=col + 1)), text=""
            )
        sent = time.perf_counter()
        client.text_document_did_change(
            t.DidChangeTextDocumentParams(text_document=t.VersionedTextDocumentIdentifier(uri=uri, version=version), content_changes=[change])
        )
        while (uri, version) not in arrivals:
            await asyncio.sleep(0.0002)
            if time.perf_counter() - sent > 10:
                raise SystemExit(f"no diagnostics for version {version}")
        diag.append(arrivals[(uri, version)] - sent)
        if k % 4 == 0:
            s = time.perf_counter()
            await client.text_document_completion_async(
                t.CompletionParams(text_document=doc, position=t.Position(line=transition_line, character=len(lines[transition_line]) - len(lines[transition_line].lstrip()) + 3))
            )
            completion.append(time.perf_counter() - s)
            s = time.perf_counter()
            await client.text_document_hover_async(t.HoverParams(text_document=doc, position=t.Position(line=hover_line, character=hover_col)))
            hover.append(time.perf_counter() - s)
        if k % 10 == 0:
            s = time.perf_counter()
            await client.text_document_references_async(
                t.ReferenceParams(text_document=doc, position=t.Position(line=hover_line, character=hover_col), context=t.ReferenceContext(include_declaration=True))
            )
            references.append(time.perf_counter() - s)
    rss_end = rss_mib(pid)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()

    total_lines = sum(len(f.read_text().splitlines()) for f in files)
    print(f"workspace: {len(files)} files, {total_lines} lines; cold load to all diagnostics: {cold * 1e3:.0f} ms")
    print(f"{'measure':<42} {'p50 ms':>8} {'p95 ms':>8} {'n':>5}")
    for name, samples in [
        ("keystroke -> diagnostics (that version)", diag),
        ("completion (after =>)", completion),
        ("hover (owner class)", hover),
        ("references (class used in 2 files)", references),
    ]:
        p50, p95, n = pct(samples)
        print(f"{name:<42} {p50:>8.2f} {p95:>8.2f} {n:>5}")
    print(f"server RSS: {rss_loaded:.0f} MiB after loading, {rss_end:.0f} MiB after {keystrokes} keystrokes")


if __name__ == "__main__":
    if sys.argv[1:2] == ["linked"]:
        from bench_linked import main as linked_main

        linked_main(sys.argv[2:])
    elif sys.argv[1:2] == ["body"]:
        asyncio.run(main(sys.argv[2], sys.argv[3], int(sys.argv[4]) if len(sys.argv) > 4 else 200))
    else:
        raise SystemExit(__doc__)
