"""Layout benchmark: gudsl's layout next to Graphviz `dot` on the same generated diagrams,
scored by research/layout_metrics.py, side by side in one run.

Two families: near-trees (`class_diagram`, `activity_diagram`: 10, 50 and 200 nodes), where
layered layout has it easy, and realistic diagrams (50 and 200 nodes): class diagrams with a
random inheritance forest over ~60 % of the classes and n/2 associations between random pairs
with role names and multiplicities at both ends (`realistic_class_diagram`), and activities of
structured control flow as programs have it — sequences, guarded branches that meet again,
loops back (`realistic_activity_diagram`).

usage: python3 bench_dot.py GUDSL_BINARY LAYOUT_METRICS_PY [--quick] [--seeds N]
       python3 bench_dot.py GUDSL_BINARY LAYOUT_METRICS_PY --scale [--sizes 50,200,1000,2000] [--aspect W:H]
           [--kinds class,activity,instance]
Needs `dot` (Debian package graphviz; only the benchmark needs it, not the product). Both tools
get the same boxes (gudsl's measured node sizes, its decision and merge diamonds included), the
same edges (generalizations pointing up in both) and the same labels: the texts of gudsl's
middle, head and tail labels, in the font gudsl measures them in (DejaVu Sans, 10.2 pt). Time
is per diagram, median of 5 (gudsl: the whole `gudsl render --format layout-json` process,
parse and resolution included; dot: `dot -Tjson`). `--quick`: the realistic diagrams only, one
timing run each. `--seeds N`: the realistic diagrams also from N more random seeds (one row
each, "class 50 #2"), and a last line counting per metric on how many diagrams gudsl is
better, equal and worse than dot — one seed can flatter either tool.

`--scale`: the realistic class and activity diagrams and generated component-instance
pipelines (`realistic_instance_diagram`) at 50, 200, 1 000 and 2 000 nodes, each laid out by
dot, by ELK layered (elkjs, `elk.py`, installed from npm on first use) and by gudsl for a page
of aspect ratio `--aspect` (default 16:10; ELK is given it too, dot has no such option), side
by side: crossings, edge–node hits, label overlaps, area, width/height, whole-process time
(one run each from 1 000 nodes, else median of 3). Of gudsl's crossings, it also counts the
joins (`joins`): the metrics count a segment ending on another edge as a crossing."""

import importlib.util
import json
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import elk  # noqa: E402

# Edge labels as gudsl draws them (scene::measure::LABEL_SIZE, the bundled DejaVu Sans).
LABEL_FONT = 'fontname="DejaVu Sans", fontsize=10.2'


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


def realistic_class_diagram(n, extra=False, seed=7):
    """n classes: ~60 % extend an earlier class, n/2 associations with roles and multiplicities
    at both ends; `extra`: one more class at the end, a subclass of a random class with an
    association (bench_stability's edit)."""
    rng = random.Random(seed)
    parents = {i: rng.randrange(i) for i in range(1, n) if rng.random() < 0.6}
    associations = {}
    for k in range(n // 2):
        a, b = rng.randrange(n), rng.randrange(n)
        many = rng.choice(["0 .. *", "1", "1 .. *", "0 .. 1"])
        associations.setdefault(a, []).append(f"self [{rng.choice(['1', '0 .. 1'])}] role{k} : C{b} [{many}];")
    lines = ["ClassDiagram Bench", "{"]
    classes = [(f"C{i}", parents.get(i), associations.get(i, [])) for i in range(n)]
    if extra:
        classes.append(("Extra", rng.randrange(n), [f"self [1] extraRole : C{rng.randrange(n)} [0 .. *];"]))
    for name, parent, owned in classes:
        base = f" extends C{parent}" if parent is not None else ""
        lines += [f"    public class {name}{base}", "    {", f"        public int {name.lower()}Value;"]
        lines += [f"        {a}" for a in owned]
        lines.append("    }")
    lines.append("}")
    return "\n".join(lines) + "\n"


def realistic_activity_diagram(n, seed=11):
    """About n nodes of structured control flow: sequences of actions, if/else branches (a
    decision with a guard and an else) that meet again, loops back (a decision whose guarded
    flow returns to the loop's first node); a start and a final node."""
    rng = random.Random(seed)
    nodes = []  # [kind, name, [(guard or None, target name)]]

    def new(kind):
        node = [kind, f"a{len(nodes)}", []]
        nodes.append(node)
        return node

    def link(exits, target):
        for node, guard in exits:
            node[2].append((guard, target[1]))

    def sequence(budget):
        """Nodes for `budget` (>= 1): the first node and the (node, guard) pairs leaving it."""
        entry, exits = None, []
        while budget > 0:
            roll = rng.random()
            if roll < 0.55 or budget < 4:
                action = new("action")
                first, last, budget = action, [(action, None)], budget - 1
            elif roll < 0.8:
                decision = new("decision")
                size = min(budget - 1, rng.randint(2, 8))
                then = rng.randint(1, size)
                then_entry, then_exits = sequence(then)
                decision[2].append((f"i < {len(nodes)}", then_entry[1]))
                if size > then:
                    else_entry, else_exits = sequence(size - then)
                    decision[2].append(("", else_entry[1]))
                else:
                    else_exits = [(decision, "")]
                first, last, budget = decision, then_exits + else_exits, budget - 1 - size
            else:
                size = min(budget - 1, rng.randint(1, 6))
                body_entry, body_exits = sequence(size)
                check = new("decision")
                link(body_exits, check)
                check[2].append((f"i < {len(nodes)}", body_entry[1]))
                first, last, budget = body_entry, [(check, "")], budget - 1 - size
            if entry is None:
                entry = first
            else:
                link(exits, first)
            exits = last
        return entry, exits

    entry, exits = sequence(n - 2)
    link(exits, [None, "done"])
    lines = ["ActivityDiagram Bench(int k)", "{", "    public int i;", f"    start S {{ => {entry[1]}; }}"]
    for kind, name, outs in nodes:
        flows = " ".join(f"[{g}] => {t};" if g is not None else f"=> {t};" for g, t in outs)
        body = "i = i + 1; " if kind == "action" else ""
        lines.append(f"    {kind} {name} {{ {body}{flows} }}")
    lines += ["    final done;", "}"]
    return "\n".join(lines) + "\n"


def realistic_instance_diagram(n, seed=13, extra=False):
    """A component-instance pipeline of n instances of the seed's components (samples/seed,
    listing 18): cameras first, viewers last, mean filters between; each filter and viewer
    bound from one or two earlier instances, mostly recent ones, as dataflow graphs grow. (The
    seed declares no filter-to-filter connection, so `gudsl check` reports those bindings; they
    are drawn as any others.) `extra`: one more filter at the end, bound from the last filter
    before the viewers (bench_stability's edit)."""
    rng = random.Random(seed)
    cameras, viewers = max(1, n // 10), max(1, n // 10)
    kinds = ["camera"] * cameras + ["filter"] * (n - cameras - viewers) + ["viewer"] * viewers
    bound = {i: [] for i in range(n)}
    for i in range(cameras, n):
        sources = [j for j in range(max(0, i - 12), min(i, n - viewers))]
        for j in set(rng.sample(sources, min(len(sources), 1 if rng.random() < 0.7 else 2))):
            bound[j].append(i)
    port = {"camera": "CameraPortInstance", "filter": "FilterPortInstance", "viewer": "ViewerPortInstance"}
    lines = ["ComponentInstanceDiagram Bench", "{"]
    for i, kind in enumerate(kinds):
        component = {"camera": "Camera", "filter": "MeanFilter", "viewer": "Viewer"}[kind]
        lines.append(f"    I{i} instantiates ComponentClassDefinitions.{component} ( )")
        lines.append("    {")
        if kind == "camera":
            lines.append("        CameraPortInstance : CameraPort ( provider ImageOut = IImageProvider(); );")
        elif kind == "filter":
            lines.append("        FilterPortInstance : FilterPort ( processor ImageIn = IImageProcessor(); provider ImageOut = IImageProvider(); );")
        else:
            lines.append("        ViewerPortInstance : ViewerPort ( processor ImageIn = IImageProcessor(); );")
        for target in bound[i]:
            lines.append(f"        [ source {port[kind]}.ImageOut ==> target I{target}.{port[kinds[target]]}.ImageIn ]")
        if extra and i == n - viewers - 1:
            lines.append("        [ source FilterPortInstance.ImageOut ==> target X.FilterPortInstance.ImageIn ]")
        lines.append("    }")
    if extra:
        lines.append("    X instantiates ComponentClassDefinitions.MeanFilter ( )")
        lines.append("    {")
        lines.append("        FilterPortInstance : FilterPort ( processor ImageIn = IImageProcessor(); provider ImageOut = IImageProvider(); );")
        lines.append("    }")
    lines.append("}")
    return "\n".join(lines) + "\n"


def quoted(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def to_dot(layout, across=False):
    """The same boxes, edges and labels for dot: a generalization or realization is laid out
    parent first (as gudsl does, and as UML draws them upwards) and drawn back to the child;
    `across`: left to right (a component-instance diagram's dataflow), an edge between ports
    joining their instances."""
    out = [
        "digraph G {",
        f"  rankdir={'LR' if across else 'TB'}; nodesep=0.55; ranksep=0.8;",
        '  node [shape=box, fixedsize=true, label=""];',
        f"  edge [{LABEL_FONT}];",
    ]
    for node in layout["nodes"]:
        out.append(f'  "{node["id"]}" [width={node["w"] / 72:.4f}, height={node["h"] / 72:.4f}];')
    texts = {}
    for label in layout.get("labels", []):
        texts.setdefault(label["edge"], {})[label["kind"]] = label.get("text", "")
    for i, edge in enumerate(layout["edges"]):
        attributes = {"mid": "label", "head": "headlabel", "tail": "taillabel"}
        labels = [f"{attributes[k]}={quoted(t)}" for k, t in sorted(texts.get(i, {}).items())]
        ids = {n["id"] for n in layout["nodes"]}
        src, dst = elk.node_of(edge["src"], ids), elk.node_of(edge["dst"], ids)
        if edge.get("kind") in ("generalization", "realization"):
            src, dst = dst, src
            labels.append("dir=back")
        out.append(f'  "{src}" -> "{dst}" [{", ".join(labels)}];')
    out.append("}")
    return "\n".join(out) + "\n"


def joins(layout, metrics):
    """How many of the crossings layout_metrics.py counts in `layout` (gudsl's layout JSON) are
    one edge's segment ending on another edge: where bindings from one port run on one track
    and part (gudsl draws a port's bindings as a tree), and corners on another edge. The
    metrics count such a touch as a crossing; no line passes through another there. `metrics`:
    layout_metrics.py as a module (its segment intersection, ends included, is the one used)."""
    segments = [(e, a, b) for e, edge in enumerate(layout["edges"]) for a, b in zip(edge["points"], edge["points"][1:])]
    cells = {}
    for i, (_, a, b) in enumerate(segments):
        for gx in range(int(min(a[0], b[0]) // 40), int(max(a[0], b[0]) // 40) + 1):
            for gy in range(int(min(a[1], b[1]) // 40), int(max(a[1], b[1]) // 40) + 1):
                cells.setdefault((gx, gy), []).append(i)
    touches, seen = set(), set()
    for members in cells.values():
        for x, i in enumerate(members):
            for j in members[x + 1:]:
                (e, a, b), (f, c, d) = segments[i], segments[j]
                if e == f or (i, j) in seen:
                    continue
                seen.add((i, j))
                p = metrics.seg_intersection(a, b, c, d)
                if p is not None and any(abs(p[0] - q[0]) < 0.5 and abs(p[1] - q[1]) < 0.5 for q in (a, b, c, d)):
                    touches.add((min(e, f), max(e, f), round(p[0]), round(p[1])))
    return len(touches)


def score(metrics, path, fmt):
    out = subprocess.run([sys.executable, metrics, str(path), "--format", fmt], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def run(gudsl, metrics, work, name, text, repeat):
    """gudsl's and dot's layouts of `text`, timed and scored."""
    src = work / f"{name}.gudsl"
    src.write_text(text)
    out = work / name
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run([gudsl, "render", str(src), "--format", "layout-json", "-o", str(out)], check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    ours_path = out / "Bench.json"
    ours_json = json.loads(ours_path.read_text())
    dot_out, dot_ms = run_dot(ours_json, False, work, name, repeat)
    ours, theirs = score(metrics, ours_path, "neutral"), score(metrics, dot_out, "dotjson")
    return len(ours_json["edges"]), statistics.median(times) * 1e3, dot_ms, ours, theirs


def run_dot(layout, across, work, name, repeat):
    """dot's layout of gudsl's `layout` (`to_dot`), written beside the others; the median time
    of `repeat` runs in ms."""
    dot_src, dot_out = work / f"{name}.dot", work / f"{name}.dot.json"
    dot_src.write_text(to_dot(layout, across))
    dot_times = []
    for _ in range(repeat):
        start = time.perf_counter()
        with open(dot_out, "w") as f:
            subprocess.run(["dot", "-Tjson", str(dot_src)], check=True, stdout=f)
        dot_times.append(time.perf_counter() - start)
    return dot_out, statistics.median(dot_times) * 1e3


COLUMNS = [
    ("crossings", "crossings", 6),
    ("edge-node", "edge_node_hits", 5),
    ("lbl-node", "label_node_overlaps", 5),
    ("lbl-lbl", "label_label_overlaps", 5),
    ("lbl-edge", "label_edge_hits", 5),
    ("bends/e", "bends_mean", 5),
    ("area kpt2", "area", 6),
    ("aspect", "aspect", 5),
]


def cell(key, value):
    return f"{value / 1000:.0f}" if key == "area" else f"{value:g}"


def main(gudsl, metrics, quick=False, seeds=0):
    work = Path(tempfile.mkdtemp(prefix="gudsl-layout-"))
    cases = [] if quick else [(f"{k} {n}", f(n)) for k, f in [("tree class", class_diagram), ("tree activity", activity_diagram)] for n in [10, 50, 200]]
    cases += [(f"{k} {n}", f(n)) for k, f in [("class", realistic_class_diagram), ("activity", realistic_activity_diagram)] for n in [50, 200]]
    cases += [
        (f"{k} {n} #{seed}", f(n, seed=100 + seed))
        for seed in range(1, seeds + 1)
        for k, f in [("class", realistic_class_diagram), ("activity", realistic_activity_diagram)]
        for n in [50, 200]
    ]
    tally = {key: [0, 0, 0] for _, key, _ in COLUMNS}
    header = f"{'diagram':<18} {'nodes':>5} {'edges':>5} {'labels':>6} | {'time ms':>13} | " + " | ".join(f"{c[0]:>{2 * c[2] + 1}}" for c in COLUMNS)
    print(header)
    print("-" * len(header))
    for k, (name, text) in enumerate(cases):
        edges, t_ours, t_dot, o, d = run(gudsl, metrics, work, f"case{k}", text, 1 if quick else 5)
        cells = " | ".join(f"{cell(key, o[key]):>{w}} {cell(key, d[key]):>{w}}" for _, key, w in COLUMNS)
        print(f"{name:<18} {o['nodes']:>5} {edges:>5} {o['labels']:>6} | {t_ours:>6.0f} {t_dot:>6.0f} | {cells}", flush=True)
        if name.startswith(("class", "activity")):
            for _, key, _ in COLUMNS:
                # Less is better for every metric (the aspect ratio, max/min side, nearer 1).
                ours, theirs = o[key], d[key]
                tally[key][0 if ours < theirs else 1 if ours == theirs else 2] += 1
    print("(each pair: gudsl, dot; label counts are gudsl's, dot is given the same texts)")
    print("realistic diagrams, gudsl better/equal/worse: " + ", ".join(f"{c} {'/'.join(map(str, tally[k]))}" for c, k, _ in COLUMNS))


def scale(gudsl, metrics, sizes, aspect, only=None):
    """The --scale table: dot, ELK and gudsl side by side per diagram kind and size."""
    work = Path(tempfile.mkdtemp(prefix="gudsl-scale-"))
    seed = Path(__file__).resolve().parent.parent.parent / "samples" / "seed"
    w, h = (float(v) for v in aspect.split(":"))
    target = w / h
    _, elk_version = elk.ensure_elkjs()
    spec = importlib.util.spec_from_file_location("layout_metrics", metrics)
    metrics_module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(metrics_module)
    dot_version = subprocess.run(["dot", "-V"], capture_output=True, text=True).stderr.strip()
    print(f"target aspect (w/h) {target:.2f}; {dot_version}; elkjs {elk_version}")
    columns = ["crossings", "edge-node", "lbl-node", "lbl-lbl", "area Mpx2", "w/h", "time ms"]
    print(f"{'diagram':<18} {'nodes':>5} {'edges':>5} | " + " | ".join(f"{c + ' dot/ELK/gudsl':>26}" for c in columns))
    kinds = [("class", realistic_class_diagram, False), ("activity", realistic_activity_diagram, False), ("instance", realistic_instance_diagram, True)]
    kinds = [k for k in kinds if k[0] in only] if only else kinds
    for kind, make, across in kinds:
        for n in sizes:
            name = f"{kind}{n}"
            src = work / f"{name}.gudsl"
            src.write_text(make(n))
            repeat = 1 if n >= 1000 else 3
            paths = [src] + ([seed] if across else [])
            out = work / name
            times = []
            for _ in range(repeat):
                start = time.perf_counter()
                subprocess.run([gudsl, "render", *map(str, paths), "--diagram", "Bench", "--format", "layout-json", "--aspect", aspect, "-o", str(out)], check=True, capture_output=True)
                times.append(time.perf_counter() - start)
            ours_path = out / "Bench.json"
            layout = json.loads(ours_path.read_text())
            dot_out, dot_ms = run_dot(layout, across, work, name, repeat)
            elk_out = work / f"{name}.elk.json"
            elk_time = elk.run(layout, across, target, elk_out, repeat)
            # The metrics join edges to nodes: an edge between ports is scored between their instances.
            ids = {n["id"] for n in layout["nodes"]}
            scored = dict(layout, edges=[dict(e, src=elk.node_of(e["src"], ids), dst=elk.node_of(e["dst"], ids)) for e in layout["edges"]])
            scored_path = work / f"{name}.scored.json"
            scored_path.write_text(json.dumps(scored))
            scores = [score(metrics, dot_out, "dotjson"), score(metrics, elk_out, "elk"), score(metrics, scored_path, "neutral")]
            row = [[s["crossings"] for s in scores[:2]] + [f"{scores[2]['crossings']} ({joins(scored, metrics_module)} joins)"], [s["edge_node_hits"] for s in scores],
                   [s["label_node_overlaps"] for s in scores], [s["label_label_overlaps"] for s in scores],
                   [f"{s['area'] / 1e6:.1f}" for s in scores], [f"{s['width'] / s['height']:.2f}" for s in scores],
                   [f"{dot_ms:.0f}", f"{elk_time:.0f}", f"{statistics.median(times) * 1e3:.0f}"]]
            cells = " | ".join(f"{' / '.join(map(str, r)):>26}" for r in row)
            print(f"{name:<18} {scores[2]['nodes']:>5} {len(layout['edges']):>5} | {cells}", flush=True)
    print("(each cell: dot / ELK / gudsl; areas and w/h of the drawings' bounding boxes; label counts as gudsl gives them to all three;")
    print(" joins: of gudsl's crossings, those where a segment ends on another edge rather than passing through it)")


if __name__ == "__main__":
    flags = sys.argv[3:]
    if "--scale" in flags:
        sizes = [int(v) for v in flags[flags.index("--sizes") + 1].split(",")] if "--sizes" in flags else [50, 200, 1000, 2000]
        only = flags[flags.index("--kinds") + 1].split(",") if "--kinds" in flags else None
        scale(sys.argv[1], sys.argv[2], sizes, flags[flags.index("--aspect") + 1] if "--aspect" in flags else "16:10", only)
        sys.exit(0)
    seeds = int(flags[flags.index("--seeds") + 1]) if "--seeds" in flags else 0
    main(sys.argv[1], sys.argv[2], "--quick" in flags, seeds)
