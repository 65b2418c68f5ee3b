"""Layout stability under an edit (docs/protocol.md, "Positions"), side by side with Graphviz `dot`.

The same edit, laid out before and after: one class (a subclass with an association) added to a
realistic class diagram (a random inheritance forest over ~60 % of the classes, n/2 associations
between random pairs with role names and multiplicities at both ends), and one action inserted
into a flow of an activity diagram, one filter added at the end of a 200-instance pipeline
(tests/render/bench_dot.py's). Laid out by `dot -Tjson` (the
same boxes and edges), by gudsl afresh (`gudsl render`, no memory), by gudsl afresh keeping the
rows of the layout before (`gudsl render --remember`, then the edited model rendered with that
sidecar), by gudsl's language server as an editor sees it (`gudsl/graph` before and after the
edit: the scene drawn before is kept), and by a language server started anew on the edited model
after the one before saved it (`didSave` writes the rows into the sidecar). Scored with research/layout_metrics.py --stability: mean node displacement after removing
the median shift, share of nodes moved > 20 pt, Kendall tau of the left-right order. Then pins:
10 nodes moved through `gudsl/applyGraphEdit`, the edit made, the diagram laid out afresh
(`relayout`): the pinned nodes' displacement from where they were put, and the others'.

usage: python3 bench_stability.py GUDSL_BINARY LAYOUT_METRICS_PY
Needs `dot` (Debian package graphviz)."""

import asyncio
import json
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "lsp"))
from bench_dot import activity_diagram, realistic_class_diagram, realistic_instance_diagram, to_dot  # noqa: E402
from elk import node_of  # noqa: E402

# The seed's component classes, which the pipelines instantiate.
SEED = Path(__file__).resolve().parent.parent.parent / "samples" / "seed"
from lsp_raw import start_server, stop_server  # noqa: E402


def activity_with_insert(n):
    """bench_dot's activity diagram with one action inserted into its flow, after a10."""
    text = activity_diagram(n)
    return text.replace("action a10 { i = i + 10; => a11; }", "action a10 { i = i + 10; => extra; }\n        action extra { i = i * 2; => a11; }")


def stability(metrics, a, b, fmt):
    out = subprocess.run([sys.executable, metrics, "--stability", str(a), str(b), "--format", fmt], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def render(gudsl, text, work, name, remember=False, sidecar=None, across=False):
    """`gudsl render` of `text`: with `remember`, writing the rows into the model's sidecar; with
    `sidecar`, a copy of that one beside the model; `across`: a pipeline, drawn with the seed's
    classes, its bindings scored between their instances. The layout-json and the sidecar."""
    src = work / f"{name}.gudsl"
    src.write_text(text)
    mine = Path(f"{src}.layout")
    if sidecar:
        mine.write_text(sidecar.read_text())
    out = work / name
    flags = ["--remember"] if remember else []
    paths = [str(src)] + ([str(SEED)] if across else [])
    subprocess.run([gudsl, "render", *paths, "--diagram", "Bench", "--format", "layout-json", "-o", str(out), *flags], check=True, capture_output=True)
    drawn = out / "Bench.json"
    if across:
        layout = json.loads(drawn.read_text())
        ids = {n["id"] for n in layout["nodes"]}
        layout["edges"] = [dict(e, src=node_of(e["src"], ids), dst=node_of(e["dst"], ids)) for e in layout["edges"]]
        drawn = out / "Bench.scored.json"
        drawn.write_text(json.dumps(layout))
    return drawn, mine


def dot_layout(layout_json, work, name, across=False):
    """dot's layout of the same boxes and edges (a pipeline's bindings between its ports, as
    gudsl drew them: the layout-json beside the scored one)."""
    src = work / f"{name}.dot"
    drawn = layout_json.with_name("Bench.json") if across else layout_json
    src.write_text(to_dot(json.loads(drawn.read_text()), across))
    out = work / f"{name}.dot.json"
    with open(out, "w") as f:
        subprocess.run(["dot", "-Tjson", str(src)], check=True, stdout=f)
    return out


def neutral(answer, path):
    """A `gudsl/graph` answer in the metrics script's neutral format."""
    nodes = [{"id": n["id"], "x": n["bounds"]["x"], "y": n["bounds"]["y"], "w": n["bounds"]["width"], "h": n["bounds"]["height"]} for n in answer["nodes"]]
    edges, labels = [], []
    for e in answer["edges"]:
        if e.get("labelBounds"):
            b = e["labelBounds"]
            labels.append({"edge": len(edges), "kind": "mid", "x": b["x"], "y": b["y"], "w": b["width"], "h": b["height"]})
        edges.append({"src": e["source"]["node"], "dst": e["target"]["node"], "points": [[p["x"], p["y"]] for p in e["points"]]})
    path.write_text(json.dumps({"nodes": nodes, "edges": edges, "labels": labels}))
    return path


def score(metrics, path, fmt):
    out = subprocess.run([sys.executable, metrics, str(path), "--format", fmt], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


async def editor_session(gudsl, work, name, before, after):
    """gudsl/graph before and after the edit in one session; then 10 nodes pinned, the edit
    undone and redone, and the graph laid out afresh around the pins."""
    root = work / f"{name}-editor"
    root.mkdir()
    client = await start_server(gudsl, root)
    path = root / "bench.gudsl"
    path.write_text(before)
    uri = path.as_uri()
    client.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": before}})

    async def graph(relayout=False):
        result, error = await client.request("gudsl/graph", {"textDocument": {"uri": uri}, "diagram": "Bench", "relayout": relayout})
        if error:
            raise SystemExit(f"gudsl/graph: {error}")
        return result

    def change(version, text):
        client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]})

    first = await graph()
    change(2, after)
    second = await graph()
    # Pins: every 20th node put 30 pt right of where it is drawn.
    change(3, before)
    third = await graph()
    pinned = {n["id"]: (n["bounds"]["x"] + 30, n["bounds"]["y"]) for n in third["nodes"][::20][:10]}
    moves = [{"op": "move", "element": i, "position": {"x": x, "y": y}} for i, (x, y) in pinned.items()]
    _, error = await client.request("gudsl/applyGraphEdit", {"textDocument": {"uri": uri, "version": 3}, "diagram": "Bench", "operations": moves})
    if error:
        raise SystemExit(f"gudsl/applyGraphEdit: {error}")
    change(4, after)
    fresh = await graph(relayout=True)
    drawn = {n["id"]: (n["bounds"]["x"], n["bounds"]["y"]) for n in fresh["nodes"]}
    off = [abs(drawn[i][0] - x) + abs(drawn[i][1] - y) for i, (x, y) in pinned.items()]
    await stop_server(client)
    return neutral(first, work / f"{name}-editor-1.json"), neutral(second, work / f"{name}-editor-2.json"), max(off), len(pinned)


async def reopened_session(gudsl, work, name, before, after):
    """A session that draws `before` and saves it (the rows go into the sidecar), then a new
    session on the same folder with the model edited meanwhile: both first drawings."""
    root = work / f"{name}-reopened"
    root.mkdir()
    path = root / "bench.gudsl"
    drawn = []
    for k, text in enumerate([before, after]):
        path.write_text(text)
        client = await start_server(gudsl, root)
        uri = path.as_uri()
        client.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}})
        result, error = await client.request("gudsl/graph", {"textDocument": {"uri": uri}, "diagram": "Bench"})
        if error:
            raise SystemExit(f"gudsl/graph: {error}")
        drawn.append(neutral(result, work / f"{name}-reopened-{k}.json"))
        client.notify("textDocument/didSave", {"textDocument": {"uri": uri}})
        # A request after the notification: the save is handled by then.
        await client.request("gudsl/diagrams", {"textDocument": {"uri": uri}})
        await stop_server(client)
    if not Path(f"{path}.layout").exists():
        raise SystemExit("no sidecar written on save")
    return drawn


def main(gudsl, metrics):
    work = Path(tempfile.mkdtemp(prefix="gudsl-stability-"))
    cases = [
        ("class 50, +1 class", realistic_class_diagram(50), realistic_class_diagram(50, extra=True)),
        ("class 200, +1 class", realistic_class_diagram(200), realistic_class_diagram(200, extra=True)),
        ("activity 200, +1 action", activity_diagram(200), activity_with_insert(200)),
        ("instance 200, +1 filter", realistic_instance_diagram(200), realistic_instance_diagram(200, extra=True)),
    ]
    print(f"{'edit':<26} {'layout':<24} {'mean disp pt':>12} {'% of dot':>8} {'moved >20pt':>11} {'tau x':>6} | after: {'crossings':>9} {'edge-node hits':>14} {'label-edge hits':>15}")
    for k, (what, before, after) in enumerate(cases):
        across = what.startswith("instance")
        ours1, _ = render(gudsl, before, work, f"c{k}a", across=across)
        ours2, _ = render(gudsl, after, work, f"c{k}b", across=across)
        kept1, sidecar = render(gudsl, before, work, f"c{k}ka", remember=True, across=across)
        kept2, _ = render(gudsl, after, work, f"c{k}kb", sidecar=sidecar, across=across)
        dot1, dot2 = dot_layout(ours1, work, f"c{k}a", across), dot_layout(ours2, work, f"c{k}b", across)
        dot = stability(metrics, dot1, dot2, "dotjson")
        rows = [
            ("graphviz dot", dot, score(metrics, dot2, "dotjson")),
            ("gudsl render (fresh)", stability(metrics, ours1, ours2, "neutral"), score(metrics, ours2, "neutral")),
            ("gudsl render --remember", stability(metrics, kept1, kept2, "neutral"), score(metrics, kept2, "neutral")),
        ]
        # The language server's sessions hold one model file (a pipeline needs the seed's too).
        if not across:
            editor1, editor2, pinned_off, pins = asyncio.run(editor_session(gudsl, work, f"c{k}", before, after))
            reopened1, reopened2 = asyncio.run(reopened_session(gudsl, work, f"c{k}", before, after))
            rows += [
                ("gudsl lsp (editor)", stability(metrics, editor1, editor2, "neutral"), score(metrics, editor2, "neutral")),
                ("gudsl lsp (reopened)", stability(metrics, reopened1, reopened2, "neutral"), score(metrics, reopened2, "neutral")),
            ]
        for name, s, q in rows:
            share = 100 * s["mean_disp_aligned"] / max(dot["mean_disp_aligned"], 1e-9)
            print(
                f"{what:<26} {name:<24} {s['mean_disp_aligned']:>12.1f} {share:>7.1f}% {100 * s['frac_moved_gt20']:>10.0f}% {s['order_kendall_x']:>6.2f} | "
                f"       {q['crossings']:>9} {q['edge_node_hits']:>14} {q['label_edge_hits']:>15}"
            )
        if not across:
            print(f"{what:<26} {f'{pins} pinned, relayout':<24} {pinned_off:>12.1f}   (the pinned nodes' largest displacement from where they were put, pt)")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
