"""ELK layered (elkjs, from npm) as a second anchor beside Graphviz `dot` in bench_dot.py: the
same boxes, edges, labels (middle, head and tail) and flow direction as gudsl's drawing (read
from its `--format layout-json`), laid out by `elk_layout.js`.

elkjs is installed on first use with npm into ~/.cache/gudsl-bench (only the benchmark needs it,
not the product). Options: layered, orthogonal edges, node spacing 40 and layer spacing 60 as
gudsl's, the page's aspect ratio (ELK uses it to pack parts and to wrap), wrapping by ELK's
MULTI_EDGE strategy, labels inline beside their edges as ELK places them."""

import json
import os
import subprocess
import time
from pathlib import Path

CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "gudsl-bench"
SCRIPT = Path(__file__).resolve().parent / "elk_layout.js"


def ensure_elkjs():
    """The folder holding node_modules/elkjs, installed there if missing; its version."""
    package = CACHE / "node_modules" / "elkjs" / "package.json"
    if not package.exists():
        CACHE.mkdir(parents=True, exist_ok=True)
        subprocess.run(["npm", "install", "--silent", "--prefix", str(CACHE), "elkjs"], check=True)
    return CACHE, json.loads(package.read_text())["version"]


def node_of(endpoint, ids):
    """The node an edge end names: the node itself, or the node whose id its port's id starts with."""
    if endpoint in ids:
        return endpoint
    best = max((i for i in ids if endpoint.startswith(i + ".")), key=len, default=None)
    return best


def to_elk(layout, across, aspect):
    """gudsl's layout-json as an ELK graph: its boxes' sizes, its edges (generalizations
    parent first, as gudsl lays them out) and its labels' sizes and kinds."""
    ids = {n["id"] for n in layout["nodes"]}
    labels = {}
    for label in layout.get("labels", []):
        placement = {"mid": "CENTER", "head": "HEAD", "tail": "TAIL"}[label.get("kind", "mid")]
        labels.setdefault(label["edge"], []).append(
            {"text": label.get("text", ""), "width": label["w"], "height": label["h"],
             "layoutOptions": {"elk.edgeLabels.placement": placement}, "id": f"l{len(labels)}_{placement}"})
    edges = []
    for i, edge in enumerate(layout["edges"]):
        src, dst = node_of(edge["src"], ids), node_of(edge["dst"], ids)
        if src is None or dst is None:
            continue
        if edge.get("kind") in ("generalization", "realization"):
            src, dst = dst, src
        edges.append({"id": f"e{i}", "sources": [src], "targets": [dst], "labels": labels.get(i, [])})
    return {
        "id": "root",
        "layoutOptions": {
            "elk.algorithm": "layered",
            "elk.direction": "RIGHT" if across else "DOWN",
            "elk.edgeRouting": "ORTHOGONAL",
            "elk.spacing.nodeNode": "40",
            "elk.layered.spacing.nodeNodeBetweenLayers": "60",
            "elk.aspectRatio": str(aspect),
            "elk.layered.wrapping.strategy": "MULTI_EDGE",
        },
        "children": [{"id": n["id"], "width": n["w"], "height": n["h"]} for n in layout["nodes"]],
        "edges": edges,
    }


def run(layout, across, aspect, out, repeat):
    """ELK's layout of `layout` written to `out`; the median whole-process time in ms."""
    folder, _ = ensure_elkjs()
    graph = json.dumps(to_elk(layout, across, aspect))
    env = dict(os.environ, NODE_PATH=str(folder / "node_modules"))
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        done = subprocess.run(["node", "--stack-size=65500", str(SCRIPT)], input=graph, capture_output=True, text=True, env=env, check=True)
        times.append(time.perf_counter() - start)
    out.write_text(done.stdout)
    times.sort()
    return times[len(times) // 2] * 1e3
