"""Live preview latency against `gudsl lsp` over the real protocol (no pygls).

usage: python3 bench_preview.py GUDSL_BINARY REPO_DIR [EDITS] [--cpu]

  1. Parameter edit -> `gudsl/preview` received, p50/p95: the chapter 4 sample (one 200×200
     frame; motion compensation's θ edited, so the camera, the black image correction and the
     uncompensated chain replay) and the chapter 6 sample with its three cameras at 640×480
     (one frame; the left Gaussian's σ edited). Where the time goes: the server's own
     `timings` (check and prepare, queue, run) and the stages' times from the report.
  2. Keystroke -> diagnostics of that version, p50/p95, while previews run: keystrokes in a
     comment of the chapter 6 model, live on 6 frames at 640×480, its σ edited every tenth
     keystroke so a preview is always under way; the control is the same keystrokes with the
     preview off.
Prints tables; exits 1 if the keystroke p95 while previews run is 20 ms or more."""

import asyncio
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

from lsp_raw import start_server, stop_server


def pct(samples):
    xs = sorted(samples)
    q = lambda p: xs[min(len(xs) - 1, int(round(p * (len(xs) - 1))))]
    return q(0.5), q(0.95), len(xs)


class Model:
    """A document open in the server, edited by whole-text changes."""

    def __init__(self, client, path):
        self.client, self.uri, self.text, self.version = client, path.as_uri(), path.read_text(), 1
        client.notify(
            "textDocument/didOpen",
            {"textDocument": {"uri": self.uri, "languageId": "gudsl", "version": 1, "text": self.text}},
        )

    def replace(self, old, new):
        assert old in self.text, old
        self.text = self.text.replace(old, new, 1)
        self.version += 1
        self.client.notify(
            "textDocument/didChange",
            {"textDocument": {"uri": self.uri, "version": self.version}, "contentChanges": [{"text": self.text}]},
        )
        return time.perf_counter(), self.version


async def until(predicate, what, timeout=300.0):
    deadline = time.perf_counter() + timeout
    while time.perf_counter() < deadline:
        value = predicate()
        if value:
            return value
        await asyncio.sleep(0.001)
    raise SystemExit(f"timed out waiting for {what}")


def previews(client):
    return [(at, params) for at, method, params in client.notifications if method == "gudsl/preview"]


async def preview_of(client, model, version):
    """When the preview of `model` at `version` arrived, and it."""
    mine = lambda p: p["uri"] == model.uri and p["version"] == version
    found = lambda: next(((at, p) for at, p in previews(client) if mine(p)), None)
    at, preview = await until(found, f"the preview of version {version}")
    if preview["state"] != "ran":
        raise SystemExit(f"the preview did not run: {preview['message']} {preview['problems']}")
    return at, preview


async def live(client, diagram, frames, cpu):
    result, error = await client.request(
        "workspace/executeCommand",
        {"command": "gudsl.preview", "arguments": [{"diagram": diagram, "live": True, "frames": frames, "cpu": cpu}]},
    )
    if error or not result["live"]:
        raise SystemExit(f"the preview did not go live: {error} {result}")


async def edits(client, model, diagram, values, cpu):
    """Each of `values` (old, new) applied in turn, its preview awaited: the latencies, the
    server's timings and the stages' ms per frame."""
    await live(client, diagram, 1, cpu)
    await until(lambda: any(p["diagram"] == diagram for _, p in previews(client)), "the first preview")
    latencies, timings, stages = [], [], {}
    for old, new in values:
        sent, version = model.replace(old, new)
        at, preview = await preview_of(client, model, version)
        latencies.append((at - sent) * 1e3)
        timings.append(preview["timings"])
        for stage in preview["report"]["stages"]:
            ms = stage["host_ms_per_frame"] + stage["device_ms_per_frame"]
            stages.setdefault(stage["instance"], []).append(ms)
    replayed = preview["replayed"]
    return latencies, timings, stages, replayed


def report(name, latencies, timings, stages, replayed):
    p50, p95, n = pct(latencies)
    mean = lambda key: sum(t[key] for t in timings) / len(timings)
    print(f"{name:<44} {p50:>8.1f} {p95:>8.1f} {n:>4}   prepare {mean('prepareMs'):.1f}, queued {mean('queuedMs'):.1f}, run {mean('runMs'):.1f} ms")
    top = sorted(((sum(v) / len(v), k) for k, v in stages.items()), reverse=True)[:5]
    print(f"{'':<44} replayed: {', '.join(replayed) or '-'}")
    print(f"{'':<44} slowest stages (ms/frame): " + ", ".join(f"{k} {ms:.1f}" for ms, k in top))


async def keystrokes(client, model, count, retune):
    """Keystroke -> diagnostics of that version, for `count` keystrokes in a comment; every
    tenth keystroke calls `retune` (a σ edit that starts a preview)."""
    latencies = []
    for k in range(count):
        if retune and k % 10 == 0:
            retune(k)
            await asyncio.sleep(0.05)
        old, new = ("// Chapter 6", "// Chapter 6x") if k % 2 == 0 else ("// Chapter 6x", "// Chapter 6")
        sent, version = model.replace(old, new)
        await until(lambda: client.diagnostics.get(model.uri, (None,))[0] == version, f"the diagnostics of {version}")
        latencies.append((time.perf_counter() - sent) * 1e3)
        await asyncio.sleep(0.02)
    return latencies


async def main(gudsl, repo, count, cpu):
    work = Path(tempfile.mkdtemp(prefix="gudsl-bench-preview-"))
    for sample in ("ch4_motion_compensation.gudsl", "ch6_object_scan.gudsl"):
        shutil.copy(repo / "samples" / "pipelines" / sample, work / sample)
    ch6 = work / "ch6_object_scan.gudsl"
    ch6.write_text(ch6.read_text().replace("frames = 6,", "frames = 6, width = 640, height = 480,"))
    client = await start_server(gudsl, work)
    ch4 = Model(client, work / "ch4_motion_compensation.gudsl")
    await until(lambda: ch4.uri in client.diagnostics, "the diagnostics of chapter 4", timeout=120)

    print(f"{'parameter edit -> gudsl/preview (ms)':<44} {'p50':>8} {'p95':>8} {'n':>4}")
    thetas = [(f"threshold = {v},", f"threshold = {v + 1},") for v in range(1, count + 1)]
    report("ch4, 1 frame 200×200, θ", *await edits(client, ch4, "MotionCompensationPipeline", thetas, cpu))

    scan = Model(client, ch6)
    await until(lambda: scan.uri in client.diagnostics, "the diagnostics of chapter 6", timeout=120)
    sigmas = [(f"LeftGaussian instantiates GaussianFilter (sigma = {2 + v / 10:g})",
               f"LeftGaussian instantiates GaussianFilter (sigma = {2 + (v + 1) / 10:g})") for v in range(count)]
    report("ch6, 1 frame 3 × 640×480, left σ", *await edits(client, scan, "ObjectScanPipeline", sigmas, cpu))

    print(f"\n{'keystroke -> diagnostics (ms)':<44} {'p50':>8} {'p95':>8} {'n':>4}")
    await live(client, "ObjectScanPipeline", 6, cpu)
    def retune(_):
        old = re.search(r"LeftGaussian instantiates GaussianFilter \(sigma = [0-9.]+\)", scan.text).group(0)
        sigma = float(old.split("= ")[1].rstrip(")")) + 0.5
        scan.replace(old, f"LeftGaussian instantiates GaussianFilter (sigma = {sigma:g})")

    busy = await keystrokes(client, scan, 4 * count, retune)
    ran = len(previews(client))
    p50, p95, n = pct(busy)
    print(f"{'while previews of 6 frames run (ch6)':<44} {p50:>8.1f} {p95:>8.1f} {n:>4}")
    await client.request("workspace/executeCommand", {"command": "gudsl.preview", "arguments": [{"diagram": "ObjectScanPipeline", "live": False}]})
    await asyncio.sleep(1.0)
    control = await keystrokes(client, scan, 4 * count, None)
    c50, c95, cn = pct(control)
    print(f"{'the control: preview off':<44} {c50:>8.1f} {c95:>8.1f} {cn:>4}")
    print(f"({ran} previews sent in all)")
    await stop_server(client)
    return p95 < 20


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    count = int(args[2]) if len(args) > 2 else 20
    ok = asyncio.run(main(args[0], Path(args[1]), count, "--cpu" in sys.argv))
    sys.exit(0 if ok else 1)
