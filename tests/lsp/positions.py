"""Positions over LSP (docs/protocol.md, `move` and `resize`), driven by graph.py's client: a node
moved through `gudsl/applyGraphEdit` is pinned in the layout sidecar beside the model file
(`<file>.gudsl.layout`, sorted keys), `gudsl/graphChanged` says so, and both `gudsl/graph` and
`gudsl render` draw it exactly where it was put while the other nodes stay where they were; a
resize gives a node its size; a text edit leaves pinned and unpinned nodes in place; pins of
deleted nodes are dropped; unpinning the last node removes the file; nested components are drawn
inside their parents and move with them; and the refusals: a stale version, a member instead of
a node, a missing position, a nested component moved on its own, a sidecar that is no layout
(reported in the graph, never overwritten), a document that is no file."""

import json
import subprocess
from pathlib import Path

from lsprotocol import types as t

from checks import fail, refused, wait_for

MOVES = """ClassDiagram Moves
{
    public class Shape
    {
        public float area();
    }
    public class Circle extends Shape
    {
        private float radius;
    }
    public class Square extends Shape { }
}
"""

NESTED = """ComponentDiagram Nest
{
    filter N.Pipeline
    {
        port PipeIn ( processor In : N.IImageProcessor )
        source N.Camera
        {
            port CameraPort ( provider ImageOut : N.IImageProvider )
            [CameraToFilter source CameraPort.ImageOut ==> target FilterPort.ImageIn]
        }
        filter N.MeanFilter
        {
            port FilterPort ( processor ImageIn : N.IImageProcessor )
        }
    }
    source N.Source
    {
        port SrcPort ( provider O : N.IImageProvider )
        [ToPipe source SrcPort.O ==> target PipeIn.In]
    }
}
"""


async def positions(client, seen, gudsl, workspace, graph, apply_graph_edit, text_edits, apply_edits):
    path = workspace / "moves.gudsl"
    path.write_text(MOVES)
    uri, sidecar = path.as_uri(), Path(str(path) + ".layout")
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(uri, "gudsl", 1, MOVES)))
    before = await graph(client, uri, "Moves")
    bounds = {n.id: n.bounds for n in before.nodes}
    if any(n.pinned for n in before.nodes) or sidecar.exists():
        fail("nothing is pinned before a move")

    # Move Shape to the right of everything: pinned there, nothing else moves.
    put = {"x": round(before.width) + 50.25, "y": 40}
    answer = await apply_graph_edit(client, uri, 1, "Moves", [{"op": "move", "element": "Moves.Shape", "position": put}])
    if not answer.layout.uri.endswith("moves.gudsl.layout") or answer.layout.diagram != "Moves" or getattr(answer.edit, "changes", None):
        fail(f"a move answers the sidecar it wrote and no text edit: {answer}")
    await wait_for(
        lambda: any(c.uri == uri and c.diagrams == ["Moves"] and c.version == 1 for c in seen.graph_changed),
        "gudsl/graphChanged after the move",
    )
    written = sidecar.read_text()
    if json.loads(written) != {"diagrams": {"Moves": {"Moves.Shape": put}}, "version": 1}:
        fail(f"the sidecar: {written}")
    if json.dumps(json.loads(written), indent=2, sort_keys=True) + "\n" != written:
        fail(f"the sidecar's keys are not sorted, one value per line: {written}")
    moved = await graph(client, uri, "Moves")
    for node in moved.nodes:
        b = node.bounds
        if node.id == "Moves.Shape":
            if (b.x, b.y) != (put["x"], put["y"]) or not node.pinned:
                fail(f"Shape is at ({b.x}, {b.y}), pinned {node.pinned}: it was put at {put}")
        elif (b.x, b.y) != (bounds[node.id].x, bounds[node.id].y) or node.pinned:
            fail(f"{node.id} moved from {bounds[node.id]} to {b} when Shape was moved")

    # Re-rendered from the command line: the node is where it was put.
    out = workspace.parent / "rendered-moves"
    done = subprocess.run(
        [gudsl, "render", str(path), "--format", "layout-json", "-o", str(out)], capture_output=True, text=True
    )
    if done.returncode != 0:
        fail(f"gudsl render: {done.stderr}")
    rendered = {n["id"]: n for n in json.loads((out / "Moves.json").read_text())["nodes"]}
    if (rendered["Moves.Shape"]["x"], rendered["Moves.Shape"]["y"]) != (put["x"], put["y"]):
        fail(f"gudsl render draws Shape at {rendered['Moves.Shape']}, not where it was put ({put})")

    # A resize: that size, at the place the node was drawn.
    circle = bounds["Moves.Circle"]
    size = {"width": round(circle.width) + 80, "height": round(circle.height) + 40}
    await apply_graph_edit(client, uri, 1, "Moves", [{"op": "resize", "element": "Moves.Circle", "size": size}])
    # (Square, beside Circle, makes room for it.)
    drawn = {n.id: n for n in (await graph(client, uri, "Moves")).nodes}
    resized = drawn["Moves.Circle"]
    b = resized.bounds
    # Pinned where it was drawn (stored to a hundredth of a point).
    near = abs(b.x - circle.x) <= 0.005 and abs(b.y - circle.y) <= 0.005
    if not near or (b.width, b.height) != (size["width"], size["height"]) or not resized.pinned:
        fail(f"Circle resized to {size}: {b}, pinned {resized.pinned}")

    # A text edit: a new class; what was drawn stays, and graphChanged says the diagram changed.
    seen.graph_changed.clear()
    grown = MOVES.replace("    public class Square", "    public class Triangle extends Shape { }\n    public class Square")
    change = t.TextDocumentContentChangeWholeDocument(text=grown)
    client.text_document_did_change(t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=uri, version=2), [change]))
    await wait_for(
        lambda: any(c.uri == uri and c.diagrams == ["Moves"] and c.version == 2 for c in seen.graph_changed),
        "gudsl/graphChanged after a text edit",
    )
    after = {n.id: n.bounds for n in (await graph(client, uri, "Moves")).nodes}
    expected = {i: (n.bounds.x, n.bounds.y) for i, n in drawn.items()}
    if "Moves.Triangle" not in after or any((after[i].x, after[i].y) != xy for i, xy in expected.items()):
        fail(f"after adding Triangle: {after}, expected {expected} kept")

    # Refusals, each leaving the sidecar as it was.
    kept = sidecar.read_text()
    move = {"op": "move", "element": "Moves.Square", "position": {"x": 5, "y": 5}}
    error = await refused(apply_graph_edit(client, uri, 1, "Moves", [move]), "a stale move")
    if "the edit is for version 1" not in str(error):
        fail(f"a stale move's error: {error}")
    member = {"op": "move", "element": "Moves.Circle.radius", "position": {"x": 5, "y": 5}}
    error = await refused(apply_graph_edit(client, uri, 2, "Moves", [member]), "moving a field")
    if "is no node of `Moves`" not in str(error):
        fail(f"moving a field: {error}")
    error = await refused(
        apply_graph_edit(client, uri, 2, "Moves", [{"op": "move", "element": "Moves.Square"}]), "a move without position"
    )
    if "needs `position`" not in str(error):
        fail(f"a move without a position: {error}")
    if sidecar.read_text() != kept:
        fail("a refused move changed the sidecar")

    # Shape deleted in the text: the next write drops its pin.
    answer = await apply_graph_edit(client, uri, 2, "Moves", [{"op": "delete", "element": "Moves.Shape"}])
    shapeless = apply_edits(grown, text_edits(answer))
    change = t.TextDocumentContentChangeWholeDocument(text=shapeless)
    client.text_document_did_change(t.DidChangeTextDocumentParams(t.VersionedTextDocumentIdentifier(uri=uri, version=3), [change]))
    await apply_graph_edit(client, uri, 3, "Moves", [{"op": "move", "element": "Moves.Square", "position": {"x": 20, "y": 400}}])
    pins = json.loads(sidecar.read_text())["diagrams"]["Moves"]
    if sorted(pins) != ["Moves.Circle", "Moves.Square"]:
        fail(f"the deleted Shape's pin is still there: {pins}")
    # Unpinning every node removes the file.
    unpin = [{"op": "move", "element": node, "position": None} for node in pins]
    await apply_graph_edit(client, uri, 3, "Moves", unpin)
    if sidecar.exists():
        fail(f"no pin left, yet the sidecar is there: {sidecar.read_text()}")

    # Nested components: inside their parents, moving with them, never on their own.
    nest_path = workspace / "nest.gudsl"
    nest_path.write_text(NESTED)
    nest_uri, nest_sidecar = nest_path.as_uri(), Path(str(nest_path) + ".layout")
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(nest_uri, "gudsl", 1, NESTED)))
    nodes = {n.id: n for n in (await graph(client, nest_uri, "Nest")).nodes}
    pipeline = nodes["N.Pipeline"].bounds
    for inner in ["N.Camera", "N.MeanFilter"]:
        b = nodes[inner].bounds
        inside = pipeline.x < b.x and b.x + b.width < pipeline.x + pipeline.width
        inside = inside and pipeline.y < b.y and b.y + b.height < pipeline.y + pipeline.height
        if nodes[inner].parent != "N.Pipeline" or not inside:
            fail(f"{inner} ({nodes[inner].parent}, {b}) is not drawn inside N.Pipeline ({pipeline})")
    if nodes["N.Pipeline"].parent is not None:
        fail("N.Pipeline is nested in nothing")
    move = {"op": "move", "element": "N.Camera", "position": {"x": 5, "y": 5}}
    error = await refused(apply_graph_edit(client, nest_uri, 1, "Nest", [move]), "moving a nested component")
    if "is nested in `N.Pipeline` and moves with it" not in str(error) or nest_sidecar.exists():
        fail(f"moving a nested component: {error}")
    put = {"x": round(pipeline.x) + 300.0, "y": round(pipeline.y) + 40.0}
    await apply_graph_edit(client, nest_uri, 1, "Nest", [{"op": "move", "element": "N.Pipeline", "position": put}])
    moved = {n.id: n.bounds for n in (await graph(client, nest_uri, "Nest")).nodes}
    for inner in ["N.Camera", "N.MeanFilter"]:
        was, now = nodes[inner].bounds, moved[inner]
        if (now.x - was.x, now.y - was.y) != (put["x"] - pipeline.x, put["y"] - pipeline.y):
            fail(f"{inner} did not move with N.Pipeline: {was} -> {now}")
    nest_sidecar.unlink()

    # A sidecar that is no layout: reported with the graph, a move refused, the file untouched.
    sidecar.write_text("{ not a layout")
    answer = await graph(client, uri, "Moves")
    if "moves.gudsl.layout" not in (answer.layoutError or "") or len(answer.nodes) != 3:
        fail(f"a broken sidecar: layoutError {answer.layoutError!r}, {len(answer.nodes)} nodes")
    error = await refused(apply_graph_edit(client, uri, 3, "Moves", [move | {"op": "move"}]), "a move into a broken sidecar")
    if "fix or delete it" not in str(error) or sidecar.read_text() != "{ not a layout":
        fail(f"a broken sidecar was overwritten or the error does not say what to do: {error}")
    sidecar.unlink()

    # A document that is no file has nowhere to keep positions.
    untitled = "untitled:Untitled-1"
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(untitled, "gudsl", 1, MOVES)))
    shape = {"op": "move", "element": "Moves.Shape", "position": {"x": 5, "y": 5}}
    error = await refused(apply_graph_edit(client, untitled, 1, "Moves", [shape]), "a move in an untitled document")
    if "save it first" not in str(error):
        fail(f"a move in an untitled document: {error}")

    # Saving writes the rows of the diagrams drawn into the sidecar; `gudsl render` keeps them,
    # drawing what the session drew.
    saved = workspace / "saved.gudsl"
    saved.write_text(MOVES)
    saved_uri, saved_sidecar = saved.as_uri(), Path(str(saved) + ".layout")
    client.text_document_did_open(t.DidOpenTextDocumentParams(t.TextDocumentItem(saved_uri, "gudsl", 1, MOVES)))
    drawn = await graph(client, saved_uri, "Moves")
    client.text_document_did_save(t.DidSaveTextDocumentParams(t.TextDocumentIdentifier(saved_uri)))
    await wait_for(saved_sidecar.exists, "the diagrams' rows written on save")
    rows = json.loads(saved_sidecar.read_text())["rows"]["Moves"]
    # Besides the nodes (and long edges), each row ends with where its band is: `=` and numbers.
    marks = ("=", "|")
    if sorted(e.split(" ")[0] for row in rows for e in row if e.split(" ")[0] not in marks) != sorted(n.id for n in drawn.nodes):
        fail(f"the rows saved do not hold the diagram's nodes once each: {rows}")
    if not all(any(e.startswith("= ") for e in row) for row in rows):
        fail(f"a row saved does not say where its band is: {rows}")
    # The model edited meanwhile (a class added): `gudsl render` keeps the others where the
    # session drew them; without the rows (the control) it does not.
    saved.write_text(MOVES.replace("    public class Square", "    public class Triangle extends Shape { }\n    public class Square"))
    session = {n.id: (n.bounds.x, n.bounds.y) for n in drawn.nodes}

    def rendered(name):
        out = workspace.parent / name
        done = subprocess.run([gudsl, "render", str(saved), "--format", "layout-json", "-o", str(out)], capture_output=True, text=True)
        if done.returncode != 0:
            fail(f"gudsl render: {done.stderr}")
        return {n["id"]: (n["x"], n["y"]) for n in json.loads((out / "Moves.json").read_text())["nodes"]}

    # How many classes are where the session drew them (the layout JSON holds a hundredth).
    def stayed(drawing):
        return sum(all(abs(drawing[i][k] - session[i][k]) <= 0.005 for k in (0, 1)) for i in session)

    with_rows = rendered("rendered-saved")
    saved_sidecar.unlink()
    without = rendered("rendered-unsaved")
    # Triangle goes beside its parent's other children: Square, right of it, makes room.
    if "Moves.Triangle" not in with_rows or stayed(with_rows) < 2 or stayed(without) >= stayed(with_rows):
        fail(f"adding Triangle, with the saved rows: {with_rows}, without: {without}; the session drew {session}")
