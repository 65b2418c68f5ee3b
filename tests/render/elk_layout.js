// Lays out an ELK graph (JSON on stdin) with elkjs and writes the laid-out graph (JSON) to
// stdout; the time elkjs took, in milliseconds, to stderr. Used by bench_dot.py (elk.py).
// usage: NODE_PATH=<folder holding node_modules> node elk_layout.js < graph.json > layout.json
const ELK = require("elkjs/lib/elk.bundled.js");

let input = "";
process.stdin.on("data", (chunk) => (input += chunk));
process.stdin.on("end", async () => {
  const elk = new ELK();
  const start = process.hrtime.bigint();
  const laid = await elk.layout(JSON.parse(input));
  const took = Number(process.hrtime.bigint() - start) / 1e6;
  process.stdout.write(JSON.stringify(laid));
  process.stderr.write(`${took.toFixed(1)}\n`);
});
