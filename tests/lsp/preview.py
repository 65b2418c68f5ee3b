"""End-to-end test of the live preview (`gudsl.preview`, `gudsl/preview`): pygls's LanguageClient
drives `gudsl lsp` as an editor does. Usage: python3 preview.py PATH_TO_GUDSL REPO_DIR [--no-gpu].
Exits non-zero on the first failure.

On a copy of the chapter 4 sample: the "◉ Live preview" lens; turned on, a preview of the first
frame arrives with the accuracy figures; an edit of motion compensation's θ runs again only
what is downstream of it (the camera, the black image correction and the uncompensated chain
replay) and changes the compensated error but not the uncompensated; a comment runs nothing;
an error stops the preview with its place, and fixing it resumes it; of two edits in quick
succession only the second's preview arrives (the first is cancelled); turned off, edits run
nothing."""

import asyncio
import shutil
import sys
import tempfile
from pathlib import Path

from lsprotocol import types as t

from checks import fail, field, refused, start_client, wait_for

DIAGRAM = "MotionCompensationPipeline"
SAMPLE = "ch4_motion_compensation.gudsl"


def plain(value):
    """A notification's params as pygls gives them (named tuples) as JSON's dicts and lists."""
    if hasattr(value, "_asdict"):
        return {k: plain(v) for k, v in value._asdict().items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    return value


def drawn_stereotypes(view):
    return [n["stereotype"] for n in view["nodes"] if n["stereotype"]]


def figure(notification, name):
    """A figure of the preview's report, by name."""
    found = [f["value"] for f in notification["report"]["figures"] if f["name"] == name]
    if len(found) != 1:
        fail(f"one figure {name} expected: {notification['report']['figures']}")
    return found[0]


class Document:
    """The sample open in the client, edited by whole-text changes."""

    def __init__(self, client, path):
        self.client, self.uri, self.text, self.version = client, path.as_uri(), path.read_text(), 1
        client.text_document_did_open(
            t.DidOpenTextDocumentParams(
                text_document=t.TextDocumentItem(uri=self.uri, language_id="gudsl", version=1, text=self.text)
            )
        )

    def replace(self, old, new):
        if old not in self.text:
            fail(f"{old!r} is not in the document")
        self.text = self.text.replace(old, new, 1)
        return self.changed()

    def changed(self):
        """The new text sent as the next version; that version."""
        self.version += 1
        self.client.text_document_did_change(
            t.DidChangeTextDocumentParams(
                text_document=t.VersionedTextDocumentIdentifier(uri=self.uri, version=self.version),
                content_changes=[t.TextDocumentContentChangeWholeDocument(text=self.text)],
            )
        )
        return self.version

    def apply(self, edit):
        """A workspace edit of this document applied as the editor applies it (one change)."""
        lines = self.text.split("\n")
        offset = lambda p: sum(len(line) + 1 for line in lines[: p["line"]]) + p["character"]
        # (pygls gives the URI keys as renamed fields: the edit is of this one document)
        (edits,) = edit["changes"].values()
        changes = sorted(edits, key=lambda e: offset(e["range"]["start"]), reverse=True)
        for change in changes:
            start, end = offset(change["range"]["start"]), offset(change["range"]["end"])
            self.text = self.text[:start] + change["newText"] + self.text[end:]
        return self.changed()


async def main(gudsl, repo, gpu):
    work = Path(tempfile.mkdtemp(prefix="gudsl-lsp-preview-"))
    shutil.copy(repo / "samples" / "pipelines" / SAMPLE, work / SAMPLE)
    client, seen = await start_client("gudsl-preview-e2e", gudsl, work)
    previews = []
    client.feature("gudsl/preview")(lambda params: previews.append(plain(params)))
    if "gudsl/preview" not in seen.capabilities.experimental["gudsl"]["notifications"]:
        fail(f"gudsl/preview is not among the notifications: {seen.capabilities.experimental}")
    if "gudsl.preview" not in seen.capabilities.execute_command_provider.commands:
        fail("gudsl.preview is not among the commands")

    document = Document(client, work / SAMPLE)
    await wait_for(lambda: document.uri in seen.diagnostics, "the sample's diagnostics", timeout=60.0)
    lenses = await client.text_document_code_lens_async(
        t.CodeLensParams(text_document=t.TextDocumentIdentifier(uri=document.uri))
    )
    live_lenses = [lens for lens in lenses if lens.command.command == "gudsl.preview"]
    if [(lens.command.title, list(lens.command.arguments)) for lens in live_lenses] != [("◉ Live preview", [{"diagram": DIAGRAM}])]:
        fail(f"one ◉ Live preview lens naming the diagram expected: {lenses}")

    async def graph():
        params = {"textDocument": {"uri": document.uri}, "diagram": DIAGRAM}
        return plain(await client.protocol.send_request_async("gudsl/graph", params))

    def node_lines(view, node):
        found = next(n for n in view["nodes"] if n["id"] == node)
        return [line for c in found["compartments"] for line in c["lines"]]

    drawn = await graph()
    if any("ms/frame" in line for n in drawn["nodes"] for c in n["compartments"] for line in c["lines"]):
        fail("times drawn on the diagram before any run")

    def after(sequence):
        """The first preview with a higher sequence than `sequence`."""
        newer = [p for p in previews if p["sequence"] > sequence]
        return newer[0] if newer else None

    async def next_preview(sequence, what):
        return await wait_for(lambda: after(sequence), what, timeout=120.0)

    state = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.preview", arguments=[{"diagram": DIAGRAM, "live": True, "cpu": not gpu}])
    )
    if state != {"diagram": DIAGRAM, "live": True, "frames": 1}:
        fail(f"the preview is live on one frame: {state}")
    first = await next_preview(0, "the first preview")
    if first["state"] != "ran" or first["report"]["frames"] != 1 or first["replayed"]:
        fail(f"the first preview runs every stage on one frame: {first}")
    if first["uri"] != document.uri or first["version"] != 1:
        fail(f"the preview names the document and its version: {first['uri']} {first['version']}")
    if not any(p.endswith(".png") and "/preview/" in p for p in first["report"]["outputs"]):
        fail(f"the sinks write into gudsl-out/<diagram>/preview: {first['report']['outputs']}")
    print(f"first preview: {first['timings']}")
    # The diagram the client fetched is drawn with the preview's times and flows.
    await wait_for(lambda: any(DIAGRAM in (field(c, "diagrams") or []) for c in seen.graph_changed), "gudsl/graphChanged after the preview")
    drawn = await graph()
    if not any("ms/frame" in line for line in node_lines(drawn, "Motion")) or drawn_stereotypes(drawn) != ["slowest"]:
        fail(f"the preview's times are not drawn: {node_lines(drawn, 'Motion')} {drawn_stereotypes(drawn)}")
    if "4×2×200×200 f32 raw" not in [e["label"] for e in drawn["edges"]]:
        fail(f"the bindings are not labelled with what they carried: {[e['label'] for e in drawn['edges']]}")

    # θ: motion compensation and what is downstream of it run; the rest replays.
    version = document.replace("threshold = 1,", "threshold = 40,")
    tuned = await next_preview(first["sequence"], "the preview of θ = 40")
    if tuned["state"] != "ran" or tuned["version"] != version:
        fail(f"the preview of version {version} expected: {tuned}")
    if tuned["replayed"] != ["Camera", "Black", "Uncompensated"]:
        fail(f"only what is downstream of Motion runs: replayed {tuned['replayed']}")
    if figure(tuned, "Uncompensated mean_cm") != figure(first, "Uncompensated mean_cm"):
        fail("the uncompensated error changed with θ")
    if figure(tuned, "Compensated mean_cm") == figure(first, "Compensated mean_cm"):
        fail("the compensated error did not change with θ")
    if node_lines(await graph(), "Camera")[-1] != "replayed (unchanged)":
        fail(f"the replayed camera is not drawn so: {node_lines(await graph(), 'Camera')}")
    print(f"θ 1 → 40: compensated {figure(first, 'Compensated mean_cm'):.3f} → {figure(tuned, 'Compensated mean_cm'):.3f} cm")

    # A control: the panel's parameters of Motion, and θ set through gudsl/setParameter.
    request = lambda method, params: client.protocol.send_request_async(method, params)
    motion = {"textDocument": {"uri": document.uri}, "diagram": DIAGRAM, "instance": "Motion"}
    shown = plain(await request("gudsl/parameters", motion))
    controls = {p["name"]: p for p in shown["parameters"]}
    theta, window = controls["threshold"], controls["windowSize"]
    if (theta["type"], theta["value"], theta["min"], theta["max"], theta["step"]) != ("float", "40", 0, 100, None):
        fail(f"θ's control: {theta}")
    if (window["type"], window["value"], window["min"], window["max"], window["step"]) != ("int", "5", 3, 15, 2):
        fail(f"MWS's control (odd, 3 to 15): {window}")
    if shown["version"] != document.version or shown["component"] != "ToF.MotionCompensation":
        fail(f"the parameters name their version and component: {shown}")
    edit = plain(await request("gudsl/setParameter", {**motion, "textDocument": {"uri": document.uri, "version": document.version}, "parameter": "threshold", "value": "3"}))
    version = document.apply(edit)
    if "threshold = 3," not in document.text:
        fail(f"setParameter wrote no `threshold = 3`: {edit}")
    slid = await next_preview(tuned["sequence"], "the preview of θ = 3 set by a control")
    if slid["version"] != version or figure(slid, "Compensated mean_cm") in (figure(tuned, "Compensated mean_cm"), figure(first, "Compensated mean_cm")):
        fail(f"the control's θ was not previewed: {slid}")
    stale = {**motion, "textDocument": {"uri": document.uri, "version": version - 1}, "parameter": "threshold", "value": "30"}
    await refused(request("gudsl/setParameter", stale), "a value for an old version")
    unknown = {**motion, "textDocument": {"uri": document.uri, "version": version}, "parameter": "thresold", "value": "30"}
    await refused(request("gudsl/setParameter", unknown), "an unknown parameter")
    document.replace("threshold = 3,", "threshold = 40,")
    tuned = await next_preview(slid["sequence"], "the preview of θ = 40 again")

    # A comment changes nothing a stage runs with: no preview.
    document.replace("ComponentInstanceDiagram", "// tuned\nComponentInstanceDiagram")
    await asyncio.sleep(1.5)
    if after(tuned["sequence"]):
        fail(f"a comment ran a preview: {after(tuned['sequence'])}")

    # An error stops it, with its place; fixed, it goes on.
    document.replace("threshold = 40,", "threshold = 40 +,")
    stopped = await next_preview(tuned["sequence"], "the stopped preview")
    if stopped["state"] != "stopped" or not stopped["problems"] or stopped["report"] is not None:
        fail(f"a model error stops the preview with its problems: {stopped}")
    if stopped["problems"][0]["uri"] != document.uri:
        fail(f"the problem is placed in the document: {stopped['problems']}")
    document.replace("threshold = 40 +,", "threshold = 40,")
    resumed = await next_preview(stopped["sequence"], "the resumed preview")
    if resumed["state"] != "ran" or figure(resumed, "Compensated mean_cm") != figure(tuned, "Compensated mean_cm"):
        fail(f"the fixed model previews as before the error: {resumed}")

    # Of two quick edits only the second's preview arrives: the first is cancelled.
    await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.preview", arguments=[{"diagram": DIAGRAM, "live": True, "frames": 6, "cpu": not gpu}])
    )
    six = await next_preview(resumed["sequence"], "the preview of 6 frames")
    if six["report"]["frames"] != 6:
        fail(f"a window of 6 frames expected: {six['report']['frames']}")
    cancelled = document.replace("threshold = 40,", "threshold = 20,")
    await asyncio.sleep(0.05)
    latest = document.replace("threshold = 20,", "threshold = 10,")
    ten = await next_preview(six["sequence"], "the preview of θ = 10")
    if ten["version"] != latest or any(p["version"] == cancelled for p in previews):
        fail(f"the first of two quick edits was previewed: {[(p['version'], p['state']) for p in previews]}")
    print(f"two quick edits: only version {latest} previewed ({ten['timings']})")

    # Off: edits run nothing.
    state = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.preview", arguments=[{"diagram": DIAGRAM, "live": False}])
    )
    if state["live"]:
        fail(f"the preview is off: {state}")
    document.replace("threshold = 10,", "threshold = 5,")
    await asyncio.sleep(1.5)
    if after(ten["sequence"]):
        fail("an edit ran a preview after it was turned off")

    await client.shutdown_async(None)
    client.exit(None)
    print("1 passed, 0 failed")


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1], Path(sys.argv[2]), "--no-gpu" not in sys.argv[3:]))
