"""End-to-end test of the graph view over LSP (docs/protocol.md): pygls's LanguageClient drives
`gudsl lsp` as a diagram client would. Usage: python3 graph.py PATH_TO_GUDSL REPO_DIR.
Exits non-zero on the first failure.

In a scratch copy of the dissertation's listings (samples/seed) it checks that the server names
the requests in its capabilities; lists every document's diagrams (`gudsl/diagrams`) and fetches
each as a graph (`gudsl/graph`): ids unique, every node with a box inside the scene, every edge
between drawn ends with a route that starts and ends on them, each node's range the text that
declares it, and the SVG it answers the very file `gudsl render` writes for the same diagram.
Then, on an open document: the version in the answers follows the editor's, ids and geometry
survive an edit that only adds a comment (ranges move with the text), a new class appears under
its fully qualified name; a rename through `gudsl/applyGraphEdit`, a stale edit refused; one edit
of each kind (create, connect, set a property, reconnect, delete) applied as an editor applies
it, each checked in the next version's graph and diagnostics; positions (positions.py: move,
resize, the layout sidecar, `gudsl/graphChanged`, a re-render); and the refusals: an unknown
diagram and an unknown document."""

import asyncio
import base64
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from lsprotocol import types as t

from checks import fail, refused, start_client, wait_for
from positions import positions

SHAPES = """ClassDiagram Shapes
{
    public abstract class Shape
    {
        public float area();
    }
    public class Circle extends Shape
    {
        private float radius;
    }
}
"""


async def graph(client, uri, diagram, svg=False):
    params = {"textDocument": {"uri": uri}, "diagram": diagram, "svg": svg}
    return await client.protocol.send_request_async("gudsl/graph", params)


async def apply_graph_edit(client, uri, version, diagram, operations):
    params = {"textDocument": {"uri": uri, "version": version}, "diagram": diagram, "operations": operations}
    return await client.protocol.send_request_async("gudsl/applyGraphEdit", params)


def text_edits(answer):
    """The text edits of a `gudsl/applyGraphEdit` answer that changes one document. (pygls gives
    an untyped answer as namedtuples, whose fields cannot be URIs: it renames them `_0`, …)"""
    changes = answer.edit.changes
    documents = list(changes)
    if len(documents) != 1:
        fail(f"one document's edits expected: {changes}")
    return documents[0]


def apply_edits(text, edits):
    for edit in sorted(edits, key=lambda e: offset(text, e.range.start), reverse=True):
        text = text[: offset(text, edit.range.start)] + edit.newText + text[offset(text, edit.range.end) :]
    return text


def offset(text, position):
    lines = text.split("\n")
    return sum(len(line) + 1 for line in lines[: position.line]) + position.character


def check_graph(answer, text, what):
    """What every graph must be: unique ids, boxes inside the scene, routes on their ends."""
    width, height = answer.width, answer.height
    nodes = {node.id: node for node in answer.nodes}
    if len(nodes) != len(answer.nodes) or len({e.id for e in answer.edges}) != len(answer.edges):
        fail(f"{what}: ids are not unique")
    for node in answer.nodes:
        b = node.bounds
        if b is None or b.x < 0 or b.y < 0 or b.x + b.width > width + 0.5 or b.y + b.height > height + 0.5:
            fail(f"{what}: {node.id}'s box {b} is not inside the scene {width}×{height}")
        written = text[offset(text, node.range.start) : offset(text, node.range.end)]
        if node.label.split(" ")[0] not in written and node.shape not in ("external", "start", "final"):
            fail(f"{what}: {node.id}'s range holds {written!r}, not its label {node.label!r}")
    for edge in answer.edges:
        ends = [nodes.get(edge.source.node), nodes.get(edge.target.node)]
        if None in ends:
            continue  # an end the model does not have: no route, the diagnostics say why
        if len(edge.points) < 2:
            fail(f"{what}: {edge.id} between drawn nodes has no route")
        for point, node, end in ((edge.points[0], ends[0], edge.source), (edge.points[-1], ends[1], edge.target)):
            port = next((p for p in node.ports if p.id == end.port), None) if end.port else None
            if port is not None:
                # A connection or a binding meets its port where the port says (several at
                # one port fanned out beside its anchor, 4.5 px at most).
                if abs(point.x - port.anchor.x) > 1 or abs(point.y - port.anchor.y) > 4.5 + 1:
                    fail(f"{what}: {edge.id} does not meet {port.id} at {port.anchor}: {point}")
                continue
            b = node.bounds
            if not (b.x - 1 <= point.x <= b.x + b.width + 1 and b.y - 1 <= point.y <= b.y + b.height + 1):
                fail(f"{what}: {edge.id} does not start or end on {node.id}: {point} vs {b}")
    # A decision or merge diamond lies on the route of every transition that leaves or enters
    # its node through it, and there is one wherever guarded flows branch.
    for control in answer.controls:
        c = control.bounds
        centre = (c.x + c.width / 2, c.y + c.height / 2)
        end = "source" if control.kind == "decision" else "target"
        through = [
            e
            for e in answer.edges
            if getattr(e, end).node == control.node
            and e.source.node != e.target.node
            and e.source.node in nodes
            and e.target.node in nodes
        ]
        passes = lambda e: any(abs(p.x - centre[0]) < 0.5 and abs(p.y - centre[1]) < 0.5 for p in e.points)
        if len(through) < 2 or not all(passes(e) for e in through):
            fail(f"{what}: not every transition at {control.node} passes its {control.kind} at {centre}")
    for node in answer.nodes:
        out = [e for e in answer.edges if e.source.node == node.id and e.target.node != node.id and e.target.node in nodes]
        branches = len(out) >= 2 and any((e.label or "").startswith("[") for e in out)
        decided = any(c.id == node.id + "#decision" for c in answer.controls)
        if branches and node.shape not in ("decision", "fork") and not decided:
            fail(f"{what}: guarded flows branch at {node.id} without a decision")


async def main(gudsl, repo):
    work = Path(tempfile.mkdtemp(prefix="gudsl-graph-"))
    workspace = work / "models"
    shutil.copytree(repo / "samples" / "seed", workspace)
    rendered = work / "rendered"
    done = subprocess.run([gudsl, "render", str(workspace), "-o", str(rendered)], capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"gudsl render: {done.stdout}\n{done.stderr}")

    client, seen = await start_client("gudsl-graph-e2e", gudsl, workspace)
    requests = seen.capabilities.experimental["gudsl"]["requests"]
    if "gudsl/graph" not in requests or "gudsl/diagrams" not in requests:
        fail(f"the requests are not named in the capabilities: {requests}")

    drawn = 0
    for path in sorted(workspace.glob("*.gudsl")):
        text = path.read_text()
        # The server reads the folder's files after `initialized`: their diagnostics say it has.
        await wait_for(lambda: path.as_uri() in seen.diagnostics, f"{path.name}'s diagnostics", timeout=60.0)
        listed = await client.protocol.send_request_async("gudsl/diagrams", {"textDocument": {"uri": path.as_uri()}})
        if listed.version is not None:
            fail(f"{path.name} is not open: no version expected, got {listed.version}")
        for diagram in listed.diagrams:
            name = text[offset(text, diagram.selectionRange.start) : offset(text, diagram.selectionRange.end)]
            if name != diagram.name or not diagram.id.endswith(diagram.name):
                fail(f"{path.name}: the selection range holds {name!r}, not {diagram.name!r}")
            answer = await graph(client, path.as_uri(), diagram.id, svg=True)
            if answer.diagram.id != diagram.id or answer.diagram.kind != diagram.kind:
                fail(f"{path.name}: asked for {diagram.id}, answered {answer.diagram}")
            check_graph(answer, text, f"{path.name}:{diagram.id}")
            if answer.svg != (rendered / f"{diagram.id}.svg").read_text():
                fail(f"{diagram.id}: the SVG differs from the one gudsl render writes")
            drawn += 1
    if drawn < 20:
        fail(f"only {drawn} diagrams drawn from the listings")

    # A long flow fitted to the view's size (`page`): first drawn for a screen (no size told
    # yet), then the view's first size lays it out afresh for it; a later size keeps the drawing
    # until a re-layout; a size that is no size is ignored (the last told is kept).
    flow = workspace / "LongFlow.gudsl"
    long_flow = (repo / "render" / "tests" / "reference" / "models" / "LongFlow.gudsl").read_text()
    flow.write_text(long_flow)
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(flow.as_uri(), "gudsl", 1, long_flow)))
    await wait_for(lambda: flow.as_uri() in seen.diagnostics, "LongFlow's diagnostics", timeout=60.0)

    async def fitted(page, relayout=False):
        params = {"textDocument": {"uri": flow.as_uri()}, "diagram": "LongFlow", "relayout": relayout}
        if page is not None:
            params["page"] = page
        answer = await client.protocol.send_request_async("gudsl/graph", params)
        return round(answer.width / answer.height, 2)

    shapes = [
        await fitted(None),
        await fitted({"width": 500, "height": 1600}),
        await fitted({"width": 1600, "height": 1000}),
        await fitted({"width": 1600, "height": 1000}, relayout=True),
        await fitted({"width": -3, "height": 1000}, relayout=True),
    ]
    print(f"LongFlow's width/height: screen, first size (tall), resized, re-laid out, no size: {shapes}")
    screen, tall, resized, wide, ignored = shapes
    if not (screen > 1.0 > tall == resized and wide > 1.0 and ignored == wide):
        fail(f"LongFlow is not fitted to the view's size as told: {shapes}")

    # The PNG a client saves ("Render Diagram to SVG/PNG…") is the one `gudsl render` writes.
    listing = workspace / "listing07_action_transitions.gudsl"
    pictures = work / "pictures"
    done = subprocess.run([gudsl, "render", str(listing), "--format", "png", "-o", str(pictures)], capture_output=True)
    answer = await client.protocol.send_request_async(
        "gudsl/graph", {"textDocument": {"uri": listing.as_uri()}, "diagram": "TransitionExample", "png": True}
    )
    png = base64.b64decode(answer.png)
    if not png.startswith(b"\x89PNG") or png != (pictures / "TransitionExample.png").read_bytes():
        fail(f"gudsl/graph's PNG ({len(png)} bytes) is not the one gudsl render writes ({done.stderr!r})")
    if getattr(answer, "svg", None) is not None:
        fail("an SVG came with the PNG though none was asked for")

    # An open document: versions, an edit that moves text, a new class.
    uri = (workspace / "shapes.gudsl").as_uri()
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(uri, "gudsl", 1, SHAPES)))
    first = await graph(client, uri, "Shapes")
    if first.version != 1 or [n.id for n in first.nodes] != ["Shapes.Shape", "Shapes.Circle"]:
        fail(f"the open document's graph: version {first.version}, nodes {[n.id for n in first.nodes]}")
    if [(e.kind, e.source.node, e.target.node) for e in first.edges] != [("generalization", "Shapes.Circle", "Shapes.Shape")]:
        fail(f"Circle extends Shape: {first.edges}")
    check_graph(first, SHAPES, "shapes.gudsl")
    commented = "// the shapes of the tutorial\n" + SHAPES
    change = t.TextDocumentContentChangeWholeDocument(text=commented)
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=uri, version=2), [change])
    )
    second = await graph(client, uri, "Shapes")
    if second.version != 2:
        fail(f"the answer describes version {second.version}, the editor has 2")
    same = [(n.id, n.bounds) for n in first.nodes] == [(n.id, n.bounds) for n in second.nodes]
    moved = all(b.range.start.line == a.range.start.line + 1 for a, b in zip(first.nodes, second.nodes))
    if not same or not moved or [e.id for e in first.edges] != [e.id for e in second.edges]:
        fail("a comment changed the graph's ids or geometry, or its ranges did not move with the text")
    grown = commented.replace("    public class Circle", "    public class Square extends Shape { }\n    public class Circle")
    change = t.TextDocumentContentChangeWholeDocument(text=grown)
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=uri, version=3), [change])
    )
    third = await graph(client, uri, "Shapes")
    if "Shapes.Square" not in [n.id for n in third.nodes] or len(third.edges) != 2:
        fail(f"the new class and its generalization: {[n.id for n in third.nodes]}, {third.edges}")
    check_graph(third, grown, "shapes.gudsl, grown")

    # A graph edit at the graph's version: the text edits that make it, applied by the client.
    edit = {"op": "rename", "element": "Shapes.Shape", "name": "Figure"}
    answer = await apply_graph_edit(client, uri, 3, "Shapes", [edit])
    edits = text_edits(answer)
    if sorted(grown[offset(grown, e.range.start) : offset(grown, e.range.end)] for e in edits) != ["Shape"] * 3:
        fail(f"renaming Shape edits its declaration and the two `extends Shape`: {edits}")
    figured = apply_edits(grown, edits)
    change = t.TextDocumentContentChangeWholeDocument(text=figured)
    client.text_document_did_change(
        t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=uri, version=4), [change])
    )
    fourth = await graph(client, uri, "Shapes")
    ends = sorted((e.source.node, e.target.node) for e in fourth.edges)
    if ends != [("Shapes.Circle", "Shapes.Figure"), ("Shapes.Square", "Shapes.Figure")] or fourth.version != 4:
        fail(f"after the rename: {ends}, version {fourth.version}")
    # The same edit against the old version: refused, and the server's text unchanged.
    error = await refused(apply_graph_edit(client, uri, 3, "Shapes", [edit]), "a stale graph edit")
    if "the edit is for version 3" not in str(error) or "the server has version 4" not in str(error):
        fail(f"a stale edit's error: {error}")
    if await client.protocol.send_request_async("gudsl/viewFileText", {"uri": uri}) != figured:
        fail("a refused edit changed the document")
    error = await refused(apply_graph_edit(client, uri, 4, "Shapes", [{"op": "teleport"}]), "an unknown operation")
    if "teleport" not in str(error):
        fail(f"an unknown operation's error: {error}")

    await edits_of_every_kind(client, seen, uri, figured)
    await positions(client, seen, gudsl, workspace, graph, apply_graph_edit, text_edits, apply_edits)

    # Refusals: what does not exist is named, with what does.
    error = await refused(graph(client, uri, "Circles"), "an unknown diagram")
    if "declares no diagram `Circles` (it declares: Shapes)" not in str(error):
        fail(f"an unknown diagram's error: {error}")
    unknown = (work / "nowhere.gudsl").as_uri()
    error = await refused(graph(client, unknown, "Shapes"), "an unknown document")
    if "is not a document of the workspace" not in str(error):
        fail(f"an unknown document's error: {error}")
    listed = await client.protocol.send_request_async("gudsl/diagrams", {"textDocument": {"uri": unknown}})
    if listed is not None:
        fail(f"an unknown document has no diagrams: {listed}")

    await client.shutdown_async(None)
    client.exit(None)
    print(f"{drawn} diagrams drawn; 1 passed, 0 failed")


FLOW = """ActivityDiagram Flow()
{
    start S { => f; }
    final f;
}
"""


async def edits_of_every_kind(client, seen, uri, text):
    """One graph edit of each kind through the protocol, each applied by the client as an editor
    does and checked in the graph and the diagnostics of the document's next version."""
    version = 4
    state = {"text": text, "version": version}

    async def step(document, diagram, operations, expect):
        answer = await apply_graph_edit(client, document, state["version"], diagram, operations)
        state["text"] = apply_edits(state["text"], text_edits(answer))
        state["version"] += 1
        change = t.TextDocumentContentChangeWholeDocument(text=state["text"])
        client.text_document_did_change(
            t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=document, version=state["version"]), [change])
        )
        after = await graph(client, document, diagram)
        if after.version != state["version"] or not expect(after):
            fail(f"{operations} gave the graph {after}\n{state['text']}")
        await wait_for(lambda: seen.diagnostics_version.get(document) == state["version"], "the diagnostics of the edit")
        syntax = [d for d in seen.diagnostics[document] if str(d.code).startswith("E000")]
        if syntax:
            fail(f"{operations} made the text unparsable: {syntax}\n{state['text']}")
        return after

    nodes = lambda g: [n.id for n in g.nodes]
    lines = lambda g, node: [i for n in g.nodes if n.id == node for c in n.compartments for i in c.ids]
    ends = lambda g: sorted((e.kind, e.source.node, e.target.node) for e in g.edges)
    await step(uri, "Shapes", [{"op": "create", "kind": "interface", "name": "Drawable"}], lambda g: "Shapes.Drawable" in nodes(g))
    field = {"op": "create", "kind": "field", "name": "sides", "parent": "Shapes.Square", "properties": {"type": "int"}}
    await step(uri, "Shapes", [field], lambda g: "Shapes.Square.sides" in lines(g, "Shapes.Square"))
    method = {"op": "create", "kind": "method", "name": "draw", "parent": "Shapes.Drawable"}
    await step(uri, "Shapes", [method], lambda g: "Shapes.Drawable.draw()" in lines(g, "Shapes.Drawable"))
    realize = {"op": "connect", "kind": "realization", "source": "Shapes.Circle", "target": "Shapes.Drawable"}
    await step(uri, "Shapes", [realize], lambda g: ("realization", "Shapes.Circle", "Shapes.Drawable") in ends(g))
    link = {"op": "connect", "kind": "association", "source": "Shapes.Square", "target": "Shapes.Circle",
            "properties": {"name": "inner", "targetMultiplicity": "0..*"}}
    g = await step(uri, "Shapes", [link], lambda g: ("association", "Shapes.Square", "Shapes.Circle") in ends(g))
    edge = next(e.id for e in g.edges if e.kind == "association")
    multiplicity = {"op": "setProperty", "element": edge, "property": "targetMultiplicity", "value": "1..4"}
    await step(uri, "Shapes", [multiplicity], lambda g: any(e.targetLabel == "1..4" for e in g.edges))
    reconnect = {"op": "reconnect", "edge": edge, "target": "Shapes.Figure"}
    await step(uri, "Shapes", [reconnect], lambda g: ("association", "Shapes.Square", "Shapes.Figure") in ends(g))
    gone = lambda g: "Shapes.Circle" not in nodes(g) and all("Shapes.Circle" not in (e.source.node, e.target.node) for e in g.edges)
    await step(uri, "Shapes", [{"op": "delete", "element": "Shapes.Circle"}], gone)

    # An activity diagram: a node, a transition with a guard, the guard changed, the node deleted.
    flow = uri.replace("shapes.gudsl", "flow.gudsl")
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(flow, "gudsl", 1, FLOW)))
    state.update(text=FLOW, version=1)
    action = {"op": "create", "kind": "loopWindow", "name": "filter"}
    await step(flow, "Flow", [action], lambda g: "Flow/filter" in nodes(g))
    arrow = {"op": "connect", "kind": "transition", "source": "Flow/S", "target": "Flow/filter", "properties": {"guard": "true"}}
    g = await step(flow, "Flow", [arrow], lambda g: any(e.label == "[true]" for e in g.edges))
    edge = next(e.id for e in g.edges if e.label == "[true]")
    guard = {"op": "setProperty", "element": edge, "property": "guard", "value": "ready"}
    await step(flow, "Flow", [guard], lambda g: any(e.label == "[ready]" for e in g.edges))
    await step(flow, "Flow", [{"op": "delete", "element": "Flow/filter"}], lambda g: nodes(g) == ["Flow/S", "Flow/f"] and len(g.edges) == 1)
    if state["text"] != FLOW:
        fail(f"creating and deleting the node did not give the text back:\n{state['text']}")
    # What the language cannot state is refused with the reason, and nothing changes.
    final = {"op": "connect", "kind": "transition", "source": "Flow/f", "target": "Flow/S"}
    error = await refused(apply_graph_edit(client, flow, state["version"], "Flow", [final]), "a transition from a final node")
    if "is a final node: no transition leaves it" not in str(error):
        fail(f"a transition from a final node: {error}")


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1], Path(sys.argv[2])))
