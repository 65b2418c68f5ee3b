"""Latency of `gudsl/graph` and `gudsl/applyGraphEdit` (docs/protocol.md) on the layout
benchmark's generated diagrams of 200 nodes (tests/render/bench_dot.py: a class diagram, an
activity diagram), as a diagram client sees it: the request's round trip through `gudsl lsp`
over stdio, the answer decoded (lsp_raw's client: no pygls, whose decoding of a large untyped
answer is the slower part).

usage: python3 bench_graph.py GUDSL_BINARY [REPEATS]
Prints, per diagram, the first `gudsl/graph` (cold: parse, resolution, graph, layout) and p50/p95
of REPEATS requests after it (warm: the document unchanged), of requests each after an edit in
another document (the graph's inputs unchanged), and of requests each after a node was added to
the diagram (laid out around the scene drawn before); then p50/p95 of REPEATS `gudsl/applyGraphEdit`
requests of each kind (the answer's text edits not applied, so each is made on the same text;
`move` writes the layout sidecar each time)."""

import asyncio
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "render"))
from bench_dot import activity_diagram, class_diagram  # noqa: E402
from lsp_raw import start_server, stop_server  # noqa: E402

OTHER = "ClassDiagram Other\n{\n    public class Note { public int n; }\n}\n"


def percentile(samples, q):
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


async def timed(client, uri, diagram):
    started = time.perf_counter()
    result, error = await client.request("gudsl/graph", {"textDocument": {"uri": uri}, "diagram": diagram})
    if error:
        raise SystemExit(f"gudsl/graph failed: {error}")
    return (time.perf_counter() - started) * 1e3, result


def add_node(text, name, k):
    """`text` with one more node, `k` naming it: a subclass of C{k}, or an action after a{k}."""
    if name.startswith("class"):
        return text.replace("\n}\n", f"\n    public class Extra{k} extends C{k} {{ public int e; }}\n}}\n")
    return text.replace("        final done;", f"        action extra{k} {{ i = i + 1; => done; }}\n        final done;").replace(
        f"action a{k} {{ i = i + {k}; => ", f"action a{k} {{ i = i + {k}; => extra{k}; => "
    )


def edits():
    """One operation of each kind on each 200-node diagram."""
    on_classes = [
        ("create a class", {"op": "create", "kind": "class", "name": "Extra"}),
        ("create a field in C100", {"op": "create", "kind": "field", "name": "extra", "parent": "Bench.C100"}),
        ("connect an association C3 -> C150", {"op": "connect", "kind": "association", "source": "Bench.C3", "target": "Bench.C150"}),
        ("rename C7 (its subclasses' extends too)", {"op": "rename", "element": "Bench.C7", "name": "Renamed"}),
        ("delete C7 (and its edges)", {"op": "delete", "element": "Bench.C7"}),
        ("setProperty: a field's type", {"op": "setProperty", "element": "Bench.C100.field100", "property": "type", "value": "float"}),
        ("move C100 (the sidecar written)", {"op": "move", "element": "Bench.C100", "position": {"x": 40, "y": 40}}),
    ]
    node = "Bench/Lane/a"
    on_activity = [
        ("create an action in the lane", {"op": "create", "kind": "action", "name": "extra", "parent": "Bench/Lane"}),
        ("connect a transition a4 -> a90, guarded", {"op": "connect", "kind": "transition", "source": node + "4", "target": node + "90", "properties": {"guard": "i > 3"}}),
        ("rename a10", {"op": "rename", "element": node + "10", "name": "renamed"}),
        ("delete a10 (and its transitions)", {"op": "delete", "element": node + "10"}),
        ("move a100 (the sidecar written)", {"op": "move", "element": node + "100", "position": {"x": 40, "y": 40}}),
    ]
    return [("class, 200 classes", class_diagram(200), on_classes), ("activity, 200 nodes", activity_diagram(200), on_activity)]


def open_document(client, uri, text):
    item = {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}
    client.notify("textDocument/didOpen", {"textDocument": item})


async def main(gudsl, repeats):
    root = Path(tempfile.mkdtemp(prefix="gudsl-graph-bench-"))
    client = await start_server(gudsl, root)
    other = (root / "other.gudsl").as_uri()
    open_document(client, other, OTHER)
    version = 1
    print(
        f"{'diagram':<22} {'nodes':>5} {'edges':>5} {'cold ms':>8} {'warm p50':>9} {'warm p95':>9} {'edit p50':>9} {'edit p95':>9} "
        f"{'+node p50':>9} {'+node p95':>9}"
    )
    for name, text in (("class, 200 classes", class_diagram(200)), ("activity, 200 nodes", activity_diagram(200))):
        uri = (root / f"{name.split(',')[0]}.gudsl").as_uri()
        open_document(client, uri, text)
        cold, answer = await timed(client, uri, "Bench")
        warm = [(await timed(client, uri, "Bench"))[0] for _ in range(repeats)]
        edited = []
        for k in range(repeats):
            version += 1
            change = {"text": OTHER.replace("int n;", f"int n{k};")}
            client.notify(
                "textDocument/didChange",
                {"textDocument": {"uri": other, "version": version}, "contentChanges": [change]},
            )
            edited.append((await timed(client, uri, "Bench"))[0])
        # Edits of the diagram itself: a node added each time, laid out around the scene before.
        grown = []
        for k in range(repeats):
            change = {"text": add_node(text, name, k)}
            client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": k + 2}, "contentChanges": [change]})
            grown.append((await timed(client, uri, "Bench"))[0])
        print(
            f"{name:<22} {len(answer['nodes']):>5} {len(answer['edges']):>5} {cold:>8.1f} "
            f"{statistics.median(warm):>9.1f} {percentile(warm, 0.95):>9.1f} "
            f"{statistics.median(edited):>9.1f} {percentile(edited, 0.95):>9.1f} "
            f"{statistics.median(grown):>9.1f} {percentile(grown, 0.95):>9.1f}"
        )
    print()
    print(f"{'gudsl/applyGraphEdit':<22} {'operation':<44} {'p50 ms':>7} {'p95 ms':>7}")
    for name, text, operations in edits():
        path = root / f"edit-{name.split(',')[0]}.gudsl"
        path.write_text(text)
        uri = path.as_uri()
        open_document(client, uri, text)
        await timed(client, uri, "Bench")
        for what, op in operations:
            times = []
            for _ in range(repeats):
                started = time.perf_counter()
                params = {"textDocument": {"uri": uri, "version": 1}, "diagram": "Bench", "operations": [op]}
                _, error = await client.request("gudsl/applyGraphEdit", params)
                if error:
                    raise SystemExit(f"{what}: {error}")
                times.append((time.perf_counter() - started) * 1e3)
            print(f"{name:<22} {what:<44} {statistics.median(times):>7.1f} {percentile(times, 0.95):>7.1f}")
    await stop_server(client)


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 30))
