#!/usr/bin/env python3
"""The pipelines' part of scripts/bench-gpu: each benchmark pipeline run by the `gudsl` binary
on the GPU and on the CPU reference, its steady state measured, one markdown report written.

A pipeline's time per frame is the steady state: the wall time from the start of frame k+1 to
the end of frame n of a run of n frames, over n − k (`frames_started_ms`, `frames_done_ms`; the
first compiles the kernels); each stage's GPU and host time per frame its work for those frames
(`report.json` gives it by frame), over n − k (a baseline binary without those figures: the
difference of its totals in that run and in a run of k frames).
GPU times are the adapter's timestamps around each pass (0 where it has none). Recorded frames
are simulated once per size and written as a ROS 2 bag (`McapWriter`) before the runs, so a
recorded run measures the pipeline alone; a simulated run includes the simulator (the CPU's).

    scripts/bench_gpu.py GUDSL OUT_DIR [--quick]
"""

import argparse
import datetime
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

# The dissertation's figures on an Intel Core i7-3770K and an NVIDIA GeForce GTX 680 (CUDA).
DISSERTATION = {
    "ch4": ("11.57 ms a frame (Table 4.2: buddha scene, MWS 5, θ 1 %, no ρ; "
            "\"a framerate of 50–100 FPS\")", 11.57),
    "ch6": ("41 ms a frame for three cameras (Table 6.2, Sec. 6.6)", 40.96),
}

CH4_STAGES = """
    Motion instantiates MotionCompensation (windowSize = 5, threshold = 1, directionRestriction = 0)
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }}
    Demod instantiates Demodulation (modulationFrequency = 20)
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Accuracy.In.depth ]
    }}
    Accuracy instantiates AccuracyReport (maxTrueDistance = 3.85{truth})
    {{
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }}
}}
"""


def camera(width, height, frames, target):
    return f"""    Camera instantiates SimulatedCamera (scene = Scene.Sphere, motion = Motion.Translation, speed = 1, frames = {frames}, width = {width}, height = {height})
    {{
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target {target}.In.frame ]
    }}
    Black instantiates BlackImageCorrection ( )
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : RawOut ( provider frame = IRawFrameProvider() );
"""


def ch4_simulated(width, height, frames):
    """Chapter 4's chain on the simulator: black image, motion compensation, demodulation,
    the accuracy against the simulator's truth."""
    return ("ComponentInstanceDiagram Bench\n{\n    import ToF.*;\n" + camera(width, height, frames, "Black")
            + "        [ source Out.frame ==> target Motion.In.frame ]\n    }\n"
            + CH4_STAGES.format(truth=""))


def ch4_recorded(bag):
    """Chapter 4's chain on recorded frames (black image subtracted when recorded)."""
    return f"""ComponentInstanceDiagram Bench
{{
    import ToF.*;
    Recording instantiates RawFrameFile (channelA = "{bag}:/Black/raw_a", channelB = "{bag}:/Black/raw_b")
    {{
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Motion.In.frame ]
    }}
""" + CH4_STAGES.format(truth=f', groundTruth = "{bag}:/Black/truth"')


def recorder(width, height, frames):
    """Simulated frames, black image subtracted, written with their truth as `frames.mcap`."""
    return ("ComponentInstanceDiagram Record\n{\n    import ToF.*;\n" + camera(width, height, frames, "Black")
            + """        [ source Out.frame ==> target Recorder.Raw.frame ]
    }
    Recorder instantiates McapWriter (fileName = "frames.mcap")
    {
        Raw : RawIn ( processor frame = IRawFrameProcessor() );
    }
}
""")


class Runner:
    def __init__(self, gudsl, work):
        self.gudsl = gudsl
        self.work = work

    def run(self, model, frames, cpu=False, sets=(), name="run"):
        """`gudsl run` of `model` (a path) for `frames` frames: its report.json."""
        return self.run_with(self.gudsl, model, frames, cpu, sets, name)

    def run_with(self, gudsl, model, frames, cpu=False, sets=(), name="run", flags=()):
        """The same with another binary (and more of `gudsl run`'s flags)."""
        out = self.work / "out" / name
        shutil.rmtree(out, ignore_errors=True)
        command = [gudsl, "run", str(model), "--root", str(self.work), "--frames", str(frames),
                   "-o", str(out)]
        command += ["--cpu"] if cpu else []
        command += list(flags)
        for value in sets:
            command += ["--set", value]
        done = subprocess.run(command, cwd=self.work, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed ({done.returncode}):\n{done.stdout}\n{done.stderr}")
        return json.loads((out / "report.json").read_text())

    def steady(self, model, frames, cpu=False, sets=(), first=1, gudsl=None, flags=()):
        """The steady state of `frames` frames after the first `first`: per frame, the wall time,
        each stage's GPU and host time and dispatches, the submissions, whether frames
        overlapped. From the run's own per-frame figures where the binary reports them, else (an
        earlier binary, a baseline) from the difference of a run of `first` frames and one of
        `frames`. A time below zero (noise over few frames) is taken as zero."""
        gudsl = gudsl or self.gudsl
        all_ = self.run_with(gudsl, model, frames, cpu, sets, "all", flags)
        if all_["frames"] <= first:
            raise RuntimeError(f"{model} gives {all_['frames']} frames; the steady state needs {first + 1}")
        if "submissions_frames" in all_:
            measured = steady_of_frames(all_, first)
        else:
            measured = steady_of_difference(self.run_with(gudsl, model, first, cpu, sets, "one", flags), all_)
        processors = {b["processor"] for b in all_["bindings"]}
        for stage, last in zip(measured["stages"], all_["stages"]):
            # What gives the frames (a binary from before `source` was reported: what no
            # binding feeds).
            stage.update({"instance": last["instance"], "component": last["component"], "async": last["async"],
                          "source": last.get("source", last["instance"] not in processors)})
        measured.update({"device": all_["device"], "frames": (first, all_["frames"]),
                         "overlapped": all_.get("frames_overlapped", False),
                         "fused": any(s.get("fused_into") for s in all_["stages"])})
        return measured


def steady_of_frames(report, k):
    """Frames k+1…n of one run: the wall time from the start of frame k+1 to the end of frame n
    (overlapped frames begin before the one before is done), each stage's work for those
    frames (`*_frames`: by the frame it was for), over n − k."""
    n = report["frames"] - k

    def mean(values, scale=1.0):
        return max(scale * sum(values[k:report["frames"]]) / n, 0.0)

    stages = [{"gpu_us": mean(s["device_ms_frames"], 1e3), "host_us": mean(s["host_ms_frames"], 1e3),
               "dispatches": round(mean(s["dispatches_frames"]), 2)} for s in report["stages"]]
    return {
        "ms": (report["frames_done_ms"][-1] - report["frames_started_ms"][k]) / n, "stages": stages,
        "dispatches": round(sum(s["dispatches"] for s in stages), 2),
        "submissions": round(mean(report["submissions_frames"]), 2),
    }


def steady_of_difference(one, all_):
    """An earlier binary's steady state: the difference of a run of k frames (`one`) and one
    of n (`all_`), over n − k; the wall time from each frame's own where it reports them."""
    k, n = one["frames"], all_["frames"] - one["frames"]

    def wall(report):
        return report["total_ms"] - report.get("loading_ms", 0.0)

    def counted(key):
        # A binary from before the counts has none.
        return round((all_[key] * all_["frames"] - one[key] * one["frames"]) / n, 2) if key in all_ else None

    stages = [{
        "gpu_us": max(1e3 * (last["device_ms_total"] - early["device_ms_total"]) / n, 0.0),
        "host_us": max(1e3 * (last["host_ms_total"] - early["host_ms_total"]) / n, 0.0),
        "dispatches": round((last.get("dispatches_per_frame", 0) * all_["frames"]
                             - early.get("dispatches_per_frame", 0) * one["frames"]) / n, 2),
    } for early, last in zip(one["stages"], all_["stages"])]
    if "frames_done_ms" in all_:
        ms = (all_["frames_done_ms"][-1] - all_["frames_started_ms"][k]) / n
    elif "frame_ms" in all_:
        ms = sum(all_["frame_ms"][k:]) / n
    else:
        ms = max(wall(all_) - wall(one), 0.0) / n
    return {"ms": ms, "stages": stages, "dispatches": counted("dispatches_per_frame"),
            "submissions": counted("submissions_per_frame")}


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        names = [line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")]
        cpu = f"{names[0]} × {len(names)}" if names else cpu
    except OSError:
        pass
    driver = "—"
    if shutil.which("nvidia-smi"):
        query = ["nvidia-smi", "--query-gpu=name,driver_version", "--format=csv,noheader"]
        done = subprocess.run(query, capture_output=True, text=True)
        driver = "NVIDIA " + done.stdout.strip().replace("\n", "; ") if done.returncode == 0 else driver
    return cpu, driver


def cases(quick):
    """(name, pipeline key, size, source, frames on the GPU, frames on the CPU); chapter 6's
    steady state is measured after its three frames of the empty scene (`emptyFrames`)."""
    sizes = [(200, 200)] if quick else [(200, 200), (640, 480)]
    for width, height in sizes:
        big = width * height > 200 * 200
        for source in ["recorded", "simulated"]:
            gpu_frames = 3 if quick else (60 if source == "recorded" else 8)
            if big and source == "simulated":
                gpu_frames = 4
            yield ("chapter 4: motion compensation", "ch4", (width, height), source, gpu_frames, 2 if quick else 4)
        yield ("chapter 5: integration time, two controllers", "ch5", (width, height), "simulated",
               2 if quick else (8 if not big else 4), 2 if quick else 3)
        yield ("chapter 6: three cameras, clouds, ICP", "ch6", (width, height), "simulated",
               4 if quick else 6, 4 if quick else 6)
    yield ("chapter 11: the component example", "ch11", None, "simulated", 2 if quick else 4, 2)


def prepare(key, size, source, work, frames):
    """The model file and the `--set`s of one case."""
    width, height = size or (0, 0)
    if key == "ch4" and source == "recorded":
        return work / f"ch4-{width}x{height}-recorded.gudsl", []
    if key == "ch4":
        return write(work / f"ch4-{width}x{height}.gudsl", ch4_simulated(width, height, frames)), []
    if key == "ch5":
        cameras = ["PerPixelCamera", "MayCamera"]
        sets = [f"{c}.{p}={v}" for c in cameras for p, v in [("width", width), ("height", height), ("frames", frames)]]
        return REPO / "samples/pipelines/ch5_integration_time.gudsl", sets
    if key == "ch6":
        cameras = ["LeftCamera", "CentreCamera", "RightCamera"]
        sets = [f"{c}.{p}={v}" for c in cameras for p, v in [("width", width), ("height", height)]]
        return REPO / "samples/pipelines/ch6_object_scan.gudsl", sets
    return REPO / "samples/pipelines/ch11_component_example.gudsl", []


def record(runner, work, size, frames):
    """Simulated frames at `size` written as a bag, and the model that reads them."""
    width, height = size
    model = write(work / f"record-{width}x{height}.gudsl", recorder(width, height, frames))
    runner.run(model, frames, name=f"record-{width}x{height}")
    bag = work / f"frames-{width}x{height}.mcap"
    shutil.copy(work / "out" / f"record-{width}x{height}" / "Recorder" / "frames.mcap", bag)
    write(work / f"ch4-{width}x{height}-recorded.gudsl", ch4_recorded(bag.name))


def pipeline_ms(measured):
    """Its time per frame without its sources' host time (never below 0)."""
    sources = sum(s["host_us"] for s in measured["stages"] if s["source"])
    return max(measured["ms"] - sources / 1e3, 0.0)


def work(measured):
    """Dispatches / submissions a frame (— where the binary does not count them)."""
    if measured["dispatches"] is None:
        return "—"
    return f"{measured['dispatches']:g} / {measured['submissions']:g}"


def fps(ms):
    return fmt(1e3 / ms if ms > 0 else None, 0)


def fmt(value, digits=1):
    return "—" if value is None else f"{value:,.{digits}f}".replace(",", " ")


def report(rows, header, quick, took):
    lines = [
        "# GPU benchmarks (`scripts/bench-gpu`" + (" --quick" if quick else "") + ")",
        "",
        f"- date: {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}",
        f"- adapter: {header['adapter']}",
        f"- driver: {header['driver']}",
        f"- CPU: {header['cpu']}",
        f"- commit: {header['commit']}",
        f"- took: {took:.0f} s",
        "",
        "Per frame in the steady state: the wall time from the start of frame k+1 to the end of frame n of a run of n frames, over n − k "
        "(k = 1: the first compiles the kernels; for chapter 6 its 3 frames of the empty scene); "
        "per stage, its work for those frames (`report.json` gives it by frame) over n − k. GPU µs: the stages' kernels by the "
        "adapter's timestamps (the passes alone; 0 without timestamp queries). Recorded: frames "
        "simulated before the runs and read from a bag; simulated: the CPU simulates each frame "
        "in the run, and *without sources* leaves the sources' host time out (the simulator, "
        "the reader of the recording): the pipeline's own time, which the dissertation's figures "
        "are of (where frames overlap, of the run one frame at a time: overlapped, the sources' host time runs "
        "beside the GPU's work). Times below zero (noise over few frames) are shown as 0.",
        "",
        "| pipeline | size | frames | k…n | ms / frame | frames / s | without sources: ms / frame | frames / s | "
        "GPU µs / frame | dispatches / submissions | CPU reference: without sources ms / frame | GPU × faster | "
        "dissertation (GTX 680) |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for row in rows:
        gpu, cpu = row["gpu"], row["cpu"]
        gpu_us = sum(s["gpu_us"] for s in gpu["stages"])
        # Overlapped, the sources' host time runs beside the GPU's work: the pipeline's own
        # time is that of its frames one at a time.
        own, cpu_own = pipeline_ms(row["apart"] or gpu), pipeline_ms(cpu) if cpu else None
        speedup = cpu_own / own if cpu_own and own > 0 else None
        figure = DISSERTATION.get(row["key"])
        versus = "—"
        if figure and row["size"] == "200×200" and own > 0:
            versus = f"{figure[0]}; this {figure[1] / own:.1f}× as fast"
        lines.append(
            f"| {row['name']} | {row['size']} | {row['source']} | {gpu['frames'][0]}…{gpu['frames'][1]} | "
            f"{fmt(gpu['ms'], 2)} | {fps(gpu['ms'])} | {fmt(own, 2)} | {fps(own)} | {fmt(gpu_us)} | "
            f"{work(gpu)} | {fmt(cpu_own, 2)} | {fmt(speedup)} | {versus} |")
    if any(row["before"] for row in rows):
        lines += ["", f"## Before and after, in this run (before: {header['baseline']})", "",
                  "| pipeline | size | frames | before: ms / frame | now | before: without sources | now | "
                  "before: dispatches / submissions | now |",
                  "|---|---|---|---:|---:|---:|---:|---:|---:|"]
        for row in rows:
            before, gpu = row["before"], row["gpu"]
            lines.append(
                f"| {row['name']} | {row['size']} | {row['source']} | {fmt(before['ms'], 2)} | {fmt(gpu['ms'], 2)} | "
                f"{fmt(pipeline_ms(before), 2)} | {fmt(pipeline_ms(gpu), 2)} | {work(before)} | {work(gpu)} |")
    if any(row["apart"] for row in rows):
        lines += ["", "## Frames overlapped, and one at a time (`--one-frame-at-a-time`), in this run", "",
                  "Where no stage needs a frame's reads for the next, frame n+1 is recorded and submitted while "
                  "the GPU works on frame n; the same pipeline one frame at a time beside it.", "",
                  "| pipeline | size | frames | one at a time: ms / frame | overlapped | × faster |",
                  "|---|---|---|---:|---:|---:|"]
        for row in (row for row in rows if row["apart"]):
            apart, gpu = row["apart"]["ms"], row["gpu"]["ms"]
            gain = fmt(apart / gpu, 2) if gpu > 0 else "—"
            lines.append(f"| {row['name']} | {row['size']} | {row['source']} | {fmt(apart, 2)} | {fmt(gpu, 2)} | {gain} |")
    if any(row["unfused"] for row in rows):
        lines += ["", "## Fused across stages, and each stage its own kernels (`--unfused`), in this run", "",
                  "A black-image correction whose every consumer takes its frames owing the black image (a "
                  "demodulation; a motion compensation with a phase calibration) runs inside their kernels "
                  "(`host/src/pipeline/fusion.rs`); the same pipeline with every stage's own kernels beside it. "
                  "GPU µs: all stages' kernels, a frame.", "",
                  "| pipeline | size | frames | unfused: ms / frame | fused | × faster | unfused: GPU µs | fused | "
                  "unfused: dispatches / submissions | fused |",
                  "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"]
        for row in (row for row in rows if row["unfused"]):
            unfused, gpu = row["unfused"], row["gpu"]
            gain = fmt(unfused["ms"] / gpu["ms"], 2) if gpu["ms"] > 0 else "—"
            kernels = [sum(s["gpu_us"] for s in m["stages"]) for m in (unfused, gpu)]
            lines.append(f"| {row['name']} | {row['size']} | {row['source']} | {fmt(unfused['ms'], 2)} | "
                         f"{fmt(gpu['ms'], 2)} | {gain} | {fmt(kernels[0])} | {fmt(kernels[1])} | "
                         f"{work(unfused)} | {work(gpu)} |")
    lines += ["", "## Stages", ""]
    for row in rows:
        lines += [f"### {row['name']}, {row['size']}, {row['source']} frames", "",
                  "| stage | component | GPU µs / frame | host µs / frame | dispatches / frame | CPU reference µs / frame |",
                  "|---|---|---:|---:|---:|---:|"]
        cpu_stages = {s["instance"]: s for s in row["cpu"]["stages"]} if row["cpu"] else {}
        for stage in row["gpu"]["stages"]:
            on_cpu = cpu_stages.get(stage["instance"])
            component = stage["component"] + (" (async)" if stage["async"] else "")
            lines.append(
                f"| {stage['instance']} | {component} | {fmt(stage['gpu_us'])} | {fmt(stage['host_us'])} | "
                f"{stage['dispatches']:g} | {fmt(on_cpu['host_us'] if on_cpu else None)} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gudsl")
    parser.add_argument("out", type=Path)
    parser.add_argument("--quick", action="store_true", help="200×200 only, a few frames (CI)")
    parser.add_argument("--baseline", help="another gudsl (an earlier commit's) run on the GPU beside it")
    args = parser.parse_args()
    started = time.monotonic()
    work = (args.out / "work").resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    runner = Runner(os.path.abspath(args.gudsl), work)
    rows = []
    recorded = set()
    for name, key, size, source, gpu_frames, cpu_frames in cases(args.quick):
        label = f"{key} {size[0]}x{size[1]}" if size else key
        print(f"bench-gpu: {label} {source} ({gpu_frames} frames; CPU reference {cpu_frames})", file=sys.stderr)
        if key == "ch4" and source == "recorded" and size not in recorded:
            record(runner, work, size, max(gpu_frames, cpu_frames))
            recorded.add(size)
        model, sets = prepare(key, size, source, work, max(gpu_frames, cpu_frames))
        first = 3 if key == "ch6" else 1
        gpu = runner.steady(model, gpu_frames, sets=sets, first=first)
        # Generated kernels (chapter 11's device diagrams) have no CPU reference.
        cpu = None if key == "ch11" else runner.steady(model, cpu_frames, cpu=True, sets=sets, first=first)
        # Frames that overlapped, once more one frame at a time: what overlapping gives.
        apart = None
        if gpu["overlapped"]:
            apart = runner.steady(model, gpu_frames, sets=sets, first=first, flags=["--one-frame-at-a-time"])
        # Stages whose kernels ran inside others', once more each with its own: what fusing gives.
        unfused = None
        if gpu["fused"]:
            unfused = runner.steady(model, gpu_frames, sets=sets, first=first, flags=["--unfused"])
        before = None
        if args.baseline:
            before = runner.steady(model, gpu_frames, sets=sets, first=first, gudsl=os.path.abspath(args.baseline))
        size_text = f"{size[0]}×{size[1]}" if size else "its own"
        rows.append({"name": name, "key": key, "size": size_text, "source": source, "gpu": gpu, "cpu": cpu,
                     "before": before, "apart": apart, "unfused": unfused})
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True, text=True)
    cpu_name, driver = machine()
    header = {"adapter": rows[0]["gpu"]["device"], "driver": driver, "cpu": cpu_name,
              "commit": commit.stdout.strip() or "—"}
    if args.baseline:
        done = subprocess.run([args.baseline, "--version"], capture_output=True, text=True)
        header["baseline"] = f"`{args.baseline}` ({done.stdout.strip() or 'its version unknown'})"
    text = report(rows, header, args.quick, time.monotonic() - started)
    path = write(args.out / "pipelines.md", text)
    (args.out / "pipelines.json").write_text(json.dumps({"header": header, "rows": rows}, indent=1))
    print(f"bench-gpu: wrote {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
