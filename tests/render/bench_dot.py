"""Layout benchmark: gudsl's layout next to Graphviz `dot` on the same generated class and
activity diagrams of 10, 50 and 200 nodes, scored by research/layout_metrics.py.

usage: python3 bench_dot.py GUDSL_BINARY LAYOUT_METRICS_PY
Needs `dot` (Debian package graphviz; only the benchmark needs it, not the product). Both tools
get the same boxes (gudsl's measured node sizes) and edges; time is per diagram (gudsl: the
whole `gudsl render --format layout-json` process, parse and resolution included; dot: `dot -Tjson`)."""

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def class_diagram(n):
    lines = ["ClassDiagram Bench", "{"]
    for i in range(n):
        base = f" extends C{(i * 7) % i}" if i > 0 else ""
        lines.append(f"    public class C{i}{base}")
        lines.append("    {")
        lines.append(f"        public int field{i};")
        lines.append(f"        public float value{i % 5};")
        if i % 4 == 3:
            lines.append(f"        self [0 .. *] items{i} : C{(i * 11 + 5) % n};")
        lines.append("    }")
    lines.append("}")
    return "\n".join(lines) + "\n"


def activity_diagram(n):
    lines = ["ActivityDiagram Bench(int k)", "{", "    public int i;", "    swimlane Lane", "    {", "        start S { => a0; }"]
    for j in range(n - 2):
        nxt = f"a{j + 1}" if j + 1 < n - 2 else "done"
        other = f"a{(j * 5 + 3) % (n - 2)}"
        if j % 3 == 2:
            lines.append(f"        decision a{j} {{ [i < {j}] => {nxt}; [] => {other}; }}")
        else:
            lines.append(f"        action a{j} {{ i = i + {j}; => {nxt}; }}")
    lines += ["        final done;", "    }", "}"]
    return "\n".join(lines) + "\n"


def to_dot(layout):
    out = ["digraph G {", "  rankdir=TB; nodesep=0.55; ranksep=0.8;", "  node [shape=box, fixedsize=true, label=\"\"];"]
    for node in layout["nodes"]:
        out.append(f'  "{node["id"]}" [width={node["w"] / 72:.4f}, height={node["h"] / 72:.4f}];')
    for edge in layout["edges"]:
        out.append(f'  "{edge["src"]}" -> "{edge["dst"]}";')
    out.append("}")
    return "\n".join(out) + "\n"


def score(metrics, path, fmt):
    out = subprocess.run([sys.executable, metrics, str(path), "--format", fmt], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(gudsl, metrics):
    work = Path(tempfile.mkdtemp(prefix="gudsl-layout-"))
    rows = []
    for kind, make in [("class", class_diagram), ("activity", activity_diagram)]:
        for n in [10, 50, 200]:
            src = work / f"{kind}{n}.gudsl"
            src.write_text(make(n))
            times = []
            for _ in range(5):
                start = time.perf_counter()
                subprocess.run([gudsl, "render", str(src), "--format", "layout-json", "-o", str(work)], check=True, capture_output=True)
                times.append(time.perf_counter() - start)
            ours_path = work / "Bench.json"
            ours_json = json.loads(ours_path.read_text())
            ours_copy = work / f"{kind}{n}.ours.json"
            ours_copy.write_text(json.dumps(ours_json))
            dot_src = work / f"{kind}{n}.dot"
            dot_src.write_text(to_dot(ours_json))
            dot_out = work / f"{kind}{n}.dot.json"
            dot_times = []
            for _ in range(5):
                start = time.perf_counter()
                with open(dot_out, "w") as f:
                    subprocess.run(["dot", "-Tjson", str(dot_src)], check=True, stdout=f)
                dot_times.append(time.perf_counter() - start)
            ours = score(metrics, ours_copy, "neutral")
            theirs = score(metrics, dot_out, "dotjson")
            rows.append((kind, n, len(ours_json["edges"]), statistics.median(times) * 1e3, statistics.median(dot_times) * 1e3, ours, theirs))
    print(f"{'diagram':<14} {'edges':>5} | {'gudsl ms':>8} {'dot ms':>8} | {'crossings':>13} | {'edge-node hits':>14} | {'area (k pt²)':>17}")
    for kind, n, e, t_ours, t_dot, o, d in rows:
        print(
            f"{kind + ' ' + str(n):<14} {e:>5} | {t_ours:>8.1f} {t_dot:>8.1f} | {o['crossings']:>6} {d['crossings']:>6} | "
            f"{o['edge_node_hits']:>6} {d['edge_node_hits']:>7} | {o['area'] / 1000:>8.0f} {d['area'] / 1000:>8.0f}"
        )
    print("(each pair: gudsl, dot)")
    import os
    if os.environ.get("FULL"):
        for kind, n, e, t_ours, t_dot, o, d in rows:
            print(kind, n, {k: (o[k], d[k]) for k in o if not isinstance(o[k], (dict, list))})


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
