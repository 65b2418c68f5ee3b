"""End-to-end test of running ToF pipelines from the editor: pygls's LanguageClient drives
`gudsl lsp` as an editor does. Usage: python3 pipeline.py PATH_TO_GUDSL REPO_DIR [--no-gpu].
Exits non-zero on the first failure.

In a scratch workspace holding the sample pipelines it reads the "▶ Run pipeline" code lenses,
runs each sample with `gudsl.runPipeline` (progress "frame k of N" with percentages) and checks
that its outputs equal those of `gudsl run` on the same files bit for bit; cancels a long run
from its progress; and shows the problems of item 2 of the issue as diagnostics of unsaved
documents (E0401 unbound input, E0402 cycle, E0403 out-of-range values, E0404 a missing and a
malformed .npy, E0405 a black image of another size than the frames), a run of such a pipeline
refused with the problems' places, and bad arguments refused. With --no-gpu, the pipelines run
on the CPU reference (`cpu: true`) and the comparison with the CLI uses `--cpu`, and the
chapter 11.5 sample (generated device code: GPU only) is checked but not run."""

import asyncio
import filecmp
import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

from lsprotocol import types as t

from checks import fail, field, refused, start_client, wait_for

# Each sample pipeline and the frames the test runs of it.
SAMPLES = {
    "ch4_motion_compensation.gudsl": ("MotionCompensationPipeline", 2),
    "ch5_integration_time.gudsl": ("IntegrationTimePipeline", 4),
    "ch6_object_scan.gudsl": ("ObjectScanPipeline", 5),
}
# Its components run generated device diagrams: on a GPU adapter (lavapipe) only.
GPU_SAMPLES = {"ch11_component_example.gudsl": ("ComponentExamplePipeline", 1)}

CAMERA = """
    Camera instantiates SimulatedCamera (frames = 2, width = 40, height = 30)
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Black.In.frame ]
    }"""


def pipeline(name, body):
    return f"ComponentInstanceDiagram {name}\n{{\n    import ToF.*;\n{body}\n}}\n"


def black(values):
    """The camera and a black-image correction with `values` (its output goes nowhere: fine)."""
    return CAMERA + f"""
    Black instantiates BlackImageCorrection ({values})
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
    }}"""


# Unsaved documents, each with the diagnostics (code, line) expected on it.
BAD = {
    "unbound.gudsl": (
        pipeline("Unbound", black("") + "\n    Writer instantiates NpyWriter ( )"),
        [("E0401", 13)],
    ),
    "values.gudsl": (
        pipeline(
            "Values",
            CAMERA.replace("Black.In", "Motion.In")
            + """
    Motion instantiates MotionCompensation (windowSize = 4, threshold = 120)
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
    }""",
        ),
        [("E0403", 9), ("E0403", 9)],
    ),
    "cycle.gudsl": (
        pipeline(
            "Cycle",
            CAMERA.replace("Black.In", "Demod.In")
            + """
    Demod instantiates Demodulation ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target A.In.depth ]
    }
    A instantiates GaussianFilter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target B.In.depth ]
    }
    B instantiates MedianFilter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target A.In.depth ]
    }""",
        ),
        [("E0402", 19)],
    ),
    "missing.gudsl": (
        pipeline("Missing", black('channelA = "nowhere_a.npy", channelB = "nowhere_b.npy"')),
        [("E0404", 9), ("E0404", 9)],
    ),
    "malformed.gudsl": (
        pipeline("Malformed", black('channelA = "bool_a.npy", channelB = "short_b.npy"')),
        [("E0404", 9), ("E0404", 9)],
    ),
    "sizes.gudsl": (
        pipeline("Sizes", black('channelA = "small_a.npy", channelB = "small_b.npy"')),
        [("E0405", 9)],
    ),
}


def npy(path, descr, shape, values):
    """A .npy file (version 1.0) of `values` (little-endian `descr`: <u2, <f4 or |b1)."""
    header = f"{{'descr': '{descr}', 'fortran_order': False, 'shape': {tuple(shape)}, }}"
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    code = {"<u2": "H", "<f4": "f", "|b1": "?"}[descr]
    body = struct.pack(f"<{len(values)}{code}", *values)
    path.write_bytes(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() + body)


async def until_cleared(diagnostics, uri):
    while diagnostics.get(uri):
        await asyncio.sleep(0.02)


def p_uri(problems):
    return {p["uri"] for p in problems}





async def main(gudsl, repo, gpu):
    work = Path(tempfile.mkdtemp(prefix="gudsl-lsp-pipeline-"))
    workspace = work / "models"
    shutil.copytree(repo / "samples" / "pipelines", workspace)
    npy(workspace / "bool_a.npy", "|b1", (4, 30, 40), [False] * 4800)
    npy(workspace / "short_b.npy", "<u2", (3, 30, 40), [0] * 3600)
    for name in ("small_a.npy", "small_b.npy"):
        npy(workspace / name, "<u2", (4, 20, 10), [0] * 800)

    client, seen = await start_client("gudsl-pipeline-e2e", gudsl, workspace)
    diagnostics, progress, shown, created = seen.diagnostics, seen.progress, seen.shown, seen.created

    for sample, (diagram, frames) in (SAMPLES | GPU_SAMPLES).items():
        uri = (workspace / sample).as_uri()
        await wait_for(lambda: uri in diagnostics, f"{sample}'s diagnostics", timeout=60.0)
        if diagnostics[uri]:
            fail(f"{sample} has diagnostics: {diagnostics[uri]}")
        lenses = await client.text_document_code_lens_async(t.CodeLensParams(text_document=t.TextDocumentIdentifier(uri=uri)))
        runs = [lens for lens in lenses if lens.command.command == "gudsl.runPipeline"]
        line = next(i for i, text in enumerate((workspace / sample).read_text().splitlines()) if text.startswith("ComponentInstanceDiagram"))
        if [(lens.command.title, lens.range.start.line) for lens in runs] != [("▶ Run pipeline", line)]:
            fail(f"one ▶ Run pipeline lens on line {line} of {sample} expected: {lenses}")
        if list(runs[0].command.arguments) != [{"diagram": diagram}]:
            fail(f"the lens names the diagram: {runs[0].command.arguments}")
        if gpu or sample in SAMPLES:
            await run_sample(client, gudsl, workspace, work, sample, diagram, frames, gpu, progress)

    await cancel_a_run(client, work, gpu, progress, created)
    await bad_pipelines(client, workspace, work, diagnostics)

    await client.shutdown_async(None)
    client.exit(None)
    print("1 passed, 0 failed")


async def run_sample(client, gudsl, workspace, work, sample, diagram, frames, gpu, progress):
    """The sample run from the editor equals `gudsl run` on the same file, file for file."""
    out = work / f"lsp-{diagram}"
    token = f"run-{diagram}"
    arguments = {"diagram": diagram, "output": str(out), "frames": frames, "cpu": not gpu}
    report = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.runPipeline", arguments=[arguments], work_done_token=token)
    )
    if report["error"] is not None or report["frames"] != frames:
        fail(f"{diagram} did not run its {frames} frames: {report}")
    if "stage" not in report["table"] or "ms/fr" not in report["table"]:
        fail(f"the stages' table expected in the answer: {report['table']}")
    plotted = diagram not in ("ObjectScanPipeline", "ComponentExamplePipeline")
    if plotted and [Path(p).name for p in report["plots"]] != ["accuracy.svg"]:
        fail(f"the accuracy plot expected among the plots: {report['plots']}")
    values = progress.get(token, [])
    kinds = [field(v, "kind") for v in values]
    if kinds[0] != "begin" or kinds[-1] != "end" or field(values[0], "percentage") != 0:
        fail(f"a bounded progress expected: {values}")
    reports = [v for v in values if field(v, "kind") == "report"]
    if field(reports[-1], "message") != f"frame {frames} of {frames}" or field(reports[-1], "percentage") != 100:
        fail(f"the frames in the progress expected: {reports}")
    if not field(values[0], "cancellable"):
        fail("the run's progress is not cancellable")

    cli = work / f"cli-{diagram}"
    command = [gudsl, "run", str(workspace / sample), "--frames", str(frames), "-o", str(cli)]
    done = subprocess.run(command + ([] if gpu else ["--cpu"]), capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"gudsl run {sample}: {done.stdout}\n{done.stderr}")
    outputs = sorted(str(Path(p).relative_to(out)) for p in report["outputs"])
    cli_outputs = sorted(str(p.relative_to(cli)) for p in cli.rglob("*") if p.is_file() and p.name != "report.json")
    if outputs != cli_outputs:
        fail(f"the editor's run wrote {outputs}, the CLI's {cli_outputs}")
    # The plots carry the CSV's numbers; images, arrays, tables and clouds are compared byte for byte.
    compared = [name for name in outputs if name.endswith((".npy", ".png", ".csv", ".ply"))]
    _, mismatch, errors = filecmp.cmpfiles(out, cli, compared, shallow=False)
    if mismatch or errors:
        fail(f"outputs differ between the editor's and the CLI's run: {mismatch} {errors}")
    print(f"{diagram}: {len(compared)} files equal to the CLI's")


async def cancel_a_run(client, work, gpu, progress, created):
    """A run cancelled from its progress stops (between frames or inside one) and says so."""
    out = work / "cancelled"
    before = len(created)
    arguments = {"diagram": "MotionCompensationPipeline", "output": str(out), "cpu": not gpu}
    request = asyncio.ensure_future(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.runPipeline", arguments=[arguments]))
    )
    token = await wait_for(lambda: created[before:] and created[-1], "a progress token created by the server", timeout=60.0)
    await wait_for(
        lambda: any(field(v, "kind") == "report" for v in progress.get(token, [])), "the run's first frame", timeout=120.0
    )
    client.window_work_done_progress_cancel(t.WorkDoneProgressCancelParams(token=token))
    report = await request
    if "cancelled" not in (report["error"] or "") or report["frames"] == len(report["outputs"]):
        fail(f"the cancelled run should say so: {report}")
    if field(progress[token][-1], "kind") != "end" or "cancelled" not in field(progress[token][-1], "message"):
        fail(f"the cancelled run's progress ends saying so: {progress[token][-1]}")
    if not (out / "report.json").exists():
        fail("a cancelled run writes its report")


async def bad_pipelines(client, workspace, work, diagnostics):
    """Item 2's problems as diagnostics while typing, and runs of such pipelines refused (each
    document open alone: a run is refused while any document has errors)."""
    out = work / "refused"
    for name, (text, expected) in BAD.items():
        uri = (workspace / name).as_uri()
        client.text_document_did_open(
            t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=uri, language_id="gudsl", version=1, text=text))
        )
        found = await wait_for(lambda: diagnostics.get(uri), f"the diagnostics of {name}")
        codes = [(str(d.code), d.range.start.line) for d in found]
        if codes != expected:
            fail(f"{name}: {expected} expected, got {codes}: {[d.message for d in found]}")
        if name == "missing.gudsl" and not ("nowhere_a.npy: does not exist" in found[0].message and "(4, H, W)" in found[0].message):
            fail(f"the missing file and the expected shape named: {found[0].message}")
        if name == "sizes.gudsl" and "the black image is 10×20, the frames it is given 40×30" not in found[0].message:
            fail(f"the sizes that cannot meet named: {found[0].message}")
        if name == "malformed.gudsl":
            messages = " | ".join(d.message for d in found)
            if "bool_a.npy has dtype bool" not in messages or "short_b.npy has shape (3, 30, 40)" not in messages or "16-bit values" not in messages:
                fail(f"the malformed files, their dtype and shape named: {messages}")
        print(f"{name}: {codes}")

        # Its run is refused with the problems' places; nothing is written.
        diagram = text.split()[1]
        error = await refused(
            client.workspace_execute_command_async(
                t.ExecuteCommandParams(command="gudsl.runPipeline", arguments=[{"diagram": diagram, "output": str(out)}])
            ),
            f"running {diagram}",
        )
        problems = (error.data or {}).get("problems", [])
        if [(p["code"], p["range"]["start"]["line"]) for p in problems] != expected or p_uri(problems) != {uri}:
            fail(f"the refusal of {diagram} names its problems: {error.message} {error.data}")
        if out.exists():
            fail("a refused run wrote output")
        client.text_document_did_close(t.DidCloseTextDocumentParams(text_document=t.TextDocumentIdentifier(uri=uri)))
        try:
            await asyncio.wait_for(until_cleared(diagnostics, uri), 10)
        except asyncio.TimeoutError:
            fail(f"{name}'s diagnostics not cleared when closed: {diagnostics.get(uri)}")

    error = await refused(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.runPipeline", arguments=["Nope"])),
        "an unknown pipeline",
    )
    if "no component-instance diagram named `Nope`" not in error.message or "MotionCompensationPipeline" not in error.message:
        fail(f"the refusal lists the pipelines: {error.message}")
    error = await refused(
        client.workspace_execute_command_async(
            t.ExecuteCommandParams(command="gudsl.runPipeline", arguments=[{"diagram": "Values", "frames": "two"}])
        ),
        "bad arguments",
    )
    if "takes a diagram's name" not in error.message:
        fail(f"bad arguments: {error.message}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail("usage: pipeline.py PATH_TO_GUDSL REPO_DIR [--no-gpu]")
    asyncio.run(main(sys.argv[1], Path(sys.argv[2]).resolve(), "--no-gpu" not in sys.argv[3:]))
