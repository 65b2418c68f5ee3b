"""End-to-end test of `gudsl lsp` driven by pygls's LanguageClient, a real LSP client this
project did not write. Usage: python3 e2e.py PATH_TO_GUDSL [SAMPLES_DIR]. Exits non-zero on the first failure.

It loads a workspace from disk, opens a document with an error, types the fix as an incremental
edit, and checks diagnostics (with versions), hover, go to definition, document symbols and
folding, with non-ASCII text (outside the BMP) before the positions it asks about."""

import asyncio
import sys
import tempfile
from pathlib import Path

from lsprotocol import types as t
from pygls.lsp.client import LanguageClient

from checks import fail, wait_for

DEFS = """ClassDiagram Defs
{
    /// An image with a width.
    public class Image
    {
        public int width;
    }
}
"""

AD = """// Größe 😀 of the image
ActivityDiagram Ad(int n)
{
    swimlane Lane, owner Defs.Imag
    {
        start S { => work; }
        action work
        {
            width = n;
            => done;
        }
        final done;
    }
}
"""


async def main(gudsl):
    root = Path(tempfile.mkdtemp(prefix="gudsl-e2e-"))
    (root / "defs.gudsl").write_text(DEFS)
    (root / "ad.gudsl").write_text(AD)
    defs_uri = (root / "defs.gudsl").as_uri()
    ad_uri = (root / "ad.gudsl").as_uri()

    client = LanguageClient("gudsl-e2e", "1.0")
    diagnostics = {}

    @client.feature(t.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: t.PublishDiagnosticsParams):
        diagnostics[params.uri] = (params.version, params.diagnostics)

    progress = []
    registrations = []

    @client.feature(t.CLIENT_REGISTER_CAPABILITY)
    def on_register(params: t.RegistrationParams):
        registrations.extend(r.method for r in params.registrations)

    @client.feature(t.WINDOW_WORK_DONE_PROGRESS_CREATE)
    def on_progress_create(params: t.WorkDoneProgressCreateParams):
        return None

    @client.feature(t.PROGRESS)
    def on_progress(params: t.ProgressParams):
        progress.append(params.value)

    await client.start_io(gudsl, "lsp")
    result = await client.initialize_async(
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
    if result.capabilities.position_encoding != t.PositionEncodingKind.Utf16:
        fail(f"position encoding {result.capabilities.position_encoding}")
    client.initialized(t.InitializedParams())

    # The workspace is loaded from disk: the broken owner is reported for the closed file.
    published = await wait_for(lambda: diagnostics.get(ad_uri), "diagnostics of the loaded workspace")
    codes = [d.code for d in published[1]]
    if "workspace/didChangeWatchedFiles" not in registrations:
        fail(f"the server did not register its file watcher: {registrations}")
    kinds = [getattr(v, "kind", None) or (v.get("kind") if isinstance(v, dict) else None) for v in progress]
    if "begin" not in kinds or "end" not in kinds:
        fail(f"workspace loading reported no $/progress begin/end: {progress}")
    if "E0202" not in codes:
        fail(f"expected E0202 for the unknown owner, got {codes}")

    # Open it, then type the missing `e` of `Defs.Image` as an incremental change.
    client.text_document_did_open(
        t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=ad_uri, language_id="gudsl", version=1, text=AD))
    )
    line = AD.splitlines().index("    swimlane Lane, owner Defs.Imag")
    col = len("    swimlane Lane, owner Defs.Imag")
    diagnostics.pop(ad_uri, None)
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(
            text_document=t.VersionedTextDocumentIdentifier(uri=ad_uri, version=2),
            content_changes=[
                t.TextDocumentContentChangePartial(
                    range=t.Range(start=t.Position(line=line, character=col), end=t.Position(line=line, character=col)),
                    text="e",
                )
            ],
        )
    )
    fixed = await wait_for(lambda: diagnostics.get(ad_uri) if diagnostics.get(ad_uri, (0,))[0] == 2 else None, "diagnostics of version 2")
    if fixed[1]:
        fail(f"expected no diagnostics after the fix, got {[(d.code, d.message) for d in fixed[1]]}")

    # Hover and definition on `Image` (after the fix) and on the owner's field `width`.
    image_col = col - 1
    hover = await client.text_document_hover_async(
        t.HoverParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=line, character=image_col))
    )
    if hover is None or "class Image" not in hover.contents.value or "An image with a width." not in hover.contents.value:
        fail(f"hover: {hover}")
    definition = await client.text_document_definition_async(
        t.DefinitionParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=line, character=image_col))
    )
    if not definition or definition[0].uri != defs_uri or definition[0].range.start.line != 3:
        fail(f"definition of Image: {definition}")
    width_line = AD.splitlines().index("            width = n;")
    definition = await client.text_document_definition_async(
        t.DefinitionParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=width_line, character=14))
    )
    if not definition or definition[0].uri != defs_uri or definition[0].range.start.line != 5:
        fail(f"definition of width: {definition}")

    # A position after the emoji: UTF-16 columns count it as two units.
    text_line0 = AD.splitlines()[0]
    utf16_col = len(text_line0[: text_line0.index("of")].encode("utf-16-le")) // 2
    if utf16_col != len(text_line0[: text_line0.index("of")]) + 1:
        fail("test setup: the emoji should take two UTF-16 units")

    symbols = await client.text_document_document_symbol_async(
        t.DocumentSymbolParams(text_document=t.TextDocumentIdentifier(uri=ad_uri))
    )
    names = [s.name for s in symbols]
    lane = symbols[0].children[0]
    if names != ["Ad"] or lane.name != "Lane" or [c.name for c in lane.children] != ["S", "work", "done"]:
        fail(f"symbols: {names}, {lane}")
    folds = await client.text_document_folding_range_async(
        t.FoldingRangeParams(text_document=t.TextDocumentIdentifier(uri=ad_uri))
    )
    if not any(f.start_line == 2 and f.end_line == 13 for f in folds):
        fail(f"folding ranges: {[(f.start_line, f.end_line) for f in folds]}")

    # Rename the class `Image` from its use in the owner clause: the declaration in defs.gudsl
    # and the use in ad.gudsl change.
    prepared = await client.text_document_prepare_rename_async(
        t.PrepareRenameParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=line, character=image_col))
    )
    if prepared is None:
        fail("prepareRename refused a class name")
    edit = await client.text_document_rename_async(
        t.RenameParams(
            text_document=t.TextDocumentIdentifier(uri=ad_uri),
            position=t.Position(line=line, character=image_col),
            new_name="Picture",
        )
    )
    changed = {uri: [(e.range.start.line, e.range.start.character, e.new_text) for e in edits] for uri, edits in edit.changes.items()}
    if changed.get(defs_uri) != [(3, 17, "Picture")] or changed.get(ad_uri) != [(line, col - 4, "Picture")]:
        fail(f"rename edits: {changed}")
    references = await client.text_document_references_async(
        t.ReferenceParams(
            text_document=t.TextDocumentIdentifier(uri=defs_uri),
            position=t.Position(line=3, character=19),
            context=t.ReferenceContext(include_declaration=False),
        )
    )
    if [(r.uri, r.range.start.line) for r in references] != [(ad_uri, line)]:
        fail(f"references: {references}")
    try:
        await client.text_document_rename_async(
            t.RenameParams(
                text_document=t.TextDocumentIdentifier(uri=ad_uri),
                position=t.Position(line=line, character=image_col),
                new_name="not a name",
            )
        )
        fail("an invalid new name was accepted")
    except Exception as error:  # the server answers with an error response
        if "not a valid name" not in str(error):
            fail(f"unexpected rename error: {error}")

    # Completion: node names after `=>`, the owner's fields inside an action.
    done_line = AD.splitlines().index("            => done;")
    completion = await client.text_document_completion_async(
        t.CompletionParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=done_line, character=15))
    )
    labels = sorted(i.label for i in (completion.items if hasattr(completion, "items") else completion))
    if labels != ["S", "done", "work"]:
        fail(f"completion after =>: {labels}")
    completion = await client.text_document_completion_async(
        t.CompletionParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=width_line, character=12))
    )
    labels = [i.label for i in (completion.items if hasattr(completion, "items") else completion)]
    if "width" not in labels or "var" not in labels or "n" not in labels:
        fail(f"completion in an action: {labels}")

    # Semantic tokens (full, then a delta against it), selection ranges, workspace symbols.
    full = await client.text_document_semantic_tokens_full_async(
        t.SemanticTokensParams(text_document=t.TextDocumentIdentifier(uri=ad_uri))
    )
    if not full.data or len(full.data) % 5 != 0 or not full.result_id:
        fail(f"semantic tokens: {full}")
    delta = await client.text_document_semantic_tokens_full_delta_async(
        t.SemanticTokensDeltaParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), previous_result_id=full.result_id)
    )
    if not hasattr(delta, "edits") or delta.edits:
        fail(f"an unchanged document should give an empty delta: {delta}")
    selections = await client.text_document_selection_range_async(
        t.SelectionRangeParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), positions=[t.Position(line=width_line, character=14)])
    )
    depth, node = 0, selections[0]
    while node is not None:
        depth, node = depth + 1, node.parent
    if depth < 5:
        fail(f"selection range chain too short: {depth}")
    symbols = await client.workspace_symbol_async(t.WorkspaceSymbolParams(query="imag"))
    # The workspace's `Image` first, then the bundled library's (`ImageContainer`, `QImage`, …).
    own = [s.name for s in symbols if not s.location.uri.startswith("gudsl:/lib/")]
    library = [s.location.uri for s in symbols[len(own):]]
    if own != ["Image"] or symbols[0].name != "Image" or not all(u.startswith("gudsl:/lib/") for u in library):
        fail(f"workspace symbols: {[(s.name, s.location.uri) for s in symbols]}")

    # Formatting returns the canonical text as one edit.
    edits = await client.text_document_formatting_async(
        t.DocumentFormattingParams(
            text_document=t.TextDocumentIdentifier(uri=ad_uri), options=t.FormattingOptions(tab_size=4, insert_spaces=True)
        )
    )
    if len(edits) != 1 or "    swimlane Lane, owner Defs.Image\n    {\n        start S\n        {\n" not in edits[0].new_text:
        fail(f"formatting: {edits}")

    # A quick fix: a transition to a node that does not exist offers to create it.
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(
            text_document=t.VersionedTextDocumentIdentifier(uri=ad_uri, version=3),
            content_changes=[t.TextDocumentContentChangeWholeDocument(text=AD.replace("Defs.Imag\n", "Defs.Image\n").replace("=> done;", "=> finish;"))],
        )
    )
    missing = await wait_for(lambda: diagnostics.get(ad_uri) if diagnostics.get(ad_uri, (0,))[0] == 3 else None, "diagnostics of version 3")
    e0204 = [d for d in missing[1] if d.code == "E0204"]
    if not e0204:
        fail(f"expected E0204 for `finish`: {[(d.code, d.message) for d in missing[1]]}")
    actions = await client.text_document_code_action_async(
        t.CodeActionParams(
            text_document=t.TextDocumentIdentifier(uri=ad_uri), range=e0204[0].range, context=t.CodeActionContext(diagnostics=e0204)
        )
    )
    titles = [a.title for a in actions]
    if "Create action node `finish`" not in titles:
        fail(f"code actions: {titles}")

    # Broken input: requests still answer.
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(
            text_document=t.VersionedTextDocumentIdentifier(uri=ad_uri, version=4),
            content_changes=[t.TextDocumentContentChangeWholeDocument(text="ActivityDiagram { swimlane")],
        )
    )
    broken = await wait_for(lambda: diagnostics.get(ad_uri) if diagnostics.get(ad_uri, (0,))[0] == 4 else None, "diagnostics of version 4")
    if not broken[1]:
        fail("expected syntax errors for the broken document")
    await client.text_document_hover_async(
        t.HoverParams(text_document=t.TextDocumentIdentifier(uri=ad_uri), position=t.Position(line=0, character=20))
    )
    await client.text_document_document_symbol_async(t.DocumentSymbolParams(text_document=t.TextDocumentIdentifier(uri=ad_uri)))

    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()


async def samples_session(gudsl, samples):
    """The dissertation's samples as a workspace: all clean; Main's calls resolve across files."""
    samples = Path(samples).resolve()
    files = sorted(samples.rglob("*.gudsl"))
    client = LanguageClient("gudsl-e2e-samples", "1.0")
    diagnostics = {}

    @client.feature(t.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: t.PublishDiagnosticsParams):
        diagnostics[params.uri] = params.diagnostics

    @client.feature(t.CLIENT_REGISTER_CAPABILITY)
    def on_register(params):
        return None

    # As vscode-languageclient starts it with `transport: stdio`.
    await client.start_io(gudsl, "lsp", "--stdio")
    await client.initialize_async(
        t.InitializeParams(process_id=None, root_uri=samples.as_uri(), capabilities=t.ClientCapabilities())
    )
    client.initialized(t.InitializedParams())
    await wait_for(lambda: len(diagnostics) >= len(files), f"diagnostics for all {len(files)} samples", timeout=30)
    dirty = {uri: [d.message for d in ds] for uri, ds in diagnostics.items() if ds}
    if dirty:
        fail(f"samples should check clean: {dirty}")
    main = samples / "seed" / "main_full.gudsl"
    text = main.read_text()
    client.text_document_did_open(
        t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=main.as_uri(), language_id="gudsl", version=1, text=text))
    )
    lines = text.splitlines()
    line = next(i for i, l in enumerate(lines) if "call MeanFilter::filterMean" in l)
    character = lines[line].index("MeanFilter") + 2
    hover = await client.text_document_hover_async(
        t.HoverParams(text_document=t.TextDocumentIdentifier(uri=main.as_uri()), position=t.Position(line=line, character=character))
    )
    if hover is None or "Filtering.Filter2.MeanFilter" not in hover.contents.value:
        fail(f"hover on MeanFilter in Main: {hover}")
    definition = await client.text_document_definition_async(
        t.DefinitionParams(text_document=t.TextDocumentIdentifier(uri=main.as_uri()), position=t.Position(line=line, character=character))
    )
    if not definition or not definition[0].uri.endswith("framework/framework.gudsl"):
        fail(f"definition of MeanFilter: {definition}")
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()


async def run_all(gudsl, samples):
    await main(gudsl)
    if samples:
        await samples_session(gudsl, samples)
    print("lsp e2e: 1 passed, 0 failed")


if __name__ == "__main__":
    asyncio.run(run_all(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None))
