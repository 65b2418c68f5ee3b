"""End-to-end test of running a model from the editor: pygls's LanguageClient drives `gudsl lsp`
on the samples as an editor does. Usage: python3 run.py PATH_TO_GUDSL SAMPLES_DIR [--no-gpu].
Exits non-zero on the first failure.

It reads the code lenses (▶ Run above `Main`, Show generated WGSL above a device diagram), opens
the generated WGSL (`gudsl.showWgsl`, then the document through `gudsl/viewFileText`), runs `Main`
with `$/progress` and `printf` output as log messages, cancels a second run from the progress
(`window/workDoneProgress/cancel`) and a third by cancelling the request (`$/cancelRequest`),
and checks the refusals: a model with errors, an unknown
diagram, bad arguments, an unknown command, and what cannot be generated as an E0301 diagnostic.
With --no-gpu, the runs themselves are skipped."""

import asyncio
import json
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types as t

from checks import fail, field, refused, start_client, wait_for

FORK = """ClassDiagram K { import OpenCL.GPU.*; public class Gpu implements OpenCL { } }
ActivityDiagram Forked()
{
    swimlane L, owner K.Gpu
    {
        start S { => split; }
        fork split { => a; => b; }
        action a { => j; }
        action b { => j; }
        join j { => f; }
        final f;
    }
}
"""





async def main(gudsl, samples, gpu):
    out = Path(tempfile.mkdtemp(prefix="gudsl-lsp-run-"))
    main_uri = (samples / "seed" / "main_full.gudsl").as_uri()
    bilateral_uri = (samples / "seed" / "listing16_bilateral_filter.gudsl").as_uri()

    client, seen = await start_client("gudsl-run-e2e", gudsl, samples)
    diagnostics, progress, shown, created = seen.diagnostics, seen.progress, seen.shown, seen.created
    logs = seen.logs
    await wait_for(lambda: main_uri in diagnostics, "the samples' diagnostics", timeout=60.0)
    if diagnostics[main_uri]:
        fail(f"main_full.gudsl has diagnostics: {diagnostics[main_uri]}")

    # Code lenses: ▶ Run above Main, Show generated WGSL above the device diagram.
    lenses = await client.text_document_code_lens_async(
        t.CodeLensParams(text_document=t.TextDocumentIdentifier(uri=main_uri))
    )
    run_lenses = [lens for lens in lenses if lens.command.command == "gudsl.run"]
    if [lens.command.title for lens in run_lenses] != ["▶ Run"] or list(run_lenses[0].command.arguments) != [{"diagram": "Main"}]:
        fail(f"one ▶ Run lens for Main expected: {lenses}")
    main_text = (samples / "seed" / "main_full.gudsl").read_text()
    main_line = next(i for i, line in enumerate(main_text.splitlines()) if line.startswith("ActivityDiagram Main"))
    if run_lenses[0].range.start.line != main_line:
        fail(f"the lens is not on Main's line {main_line}: {run_lenses[0].range}")
    lenses = await client.text_document_code_lens_async(
        t.CodeLensParams(text_document=t.TextDocumentIdentifier(uri=bilateral_uri))
    )
    wgsl_lenses = [lens for lens in lenses if lens.command.command == "gudsl.showWgsl"]
    if len(wgsl_lenses) != 1 or any(lens.command.command == "gudsl.run" for lens in lenses):
        fail(f"one Show generated WGSL lens and no ▶ Run on the bilateral filter expected: {lenses}")

    # Show generated WGSL: a read-only document, read again through gudsl/viewFileText.
    shown_wgsl = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.showWgsl", arguments=list(wgsl_lenses[0].command.arguments))
    )
    if shown_wgsl["languageId"] != "wgsl" or "@compute" not in shown_wgsl["text"]:
        fail(f"generated WGSL expected: {shown_wgsl}")
    if not shown_wgsl["uri"].startswith("gudsl:/wgsl/"):
        fail(f"a gudsl:/wgsl/ document expected: {shown_wgsl['uri']}")
    text = await client.protocol.send_request_async("gudsl/viewFileText", {"uri": shown_wgsl["uri"]})
    if text != shown_wgsl["text"]:
        fail("gudsl/viewFileText answers another text for the generated document")
    whole_file = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(command="gudsl.showWgsl", arguments=[{"uri": bilateral_uri}])
    )
    if "fn AdFilterBilateral(" not in whole_file["text"]:
        fail(f"the document's device diagrams expected: {whole_file['uri']}")

    # What cannot be generated is a diagnostic as soon as it is typed.
    fork_uri = (samples / "unsaved_fork.gudsl").as_uri()
    client.text_document_did_open(
        t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=fork_uri, language_id="gudsl", version=1, text=FORK))
    )
    fork = await wait_for(lambda: diagnostics.get(fork_uri), "E0301 on the fork")
    if [(d.code, d.range.start.line) for d in fork] != [("E0301", 6), ("E0301", 9)] or "one flow" not in fork[0].message:
        fail(f"E0301 at the fork node expected: {fork}")
    error = await refused(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.showWgsl", arguments=["Forked"])),
        "showWgsl of a diagram that cannot be generated",
    )
    if "cannot be generated" not in error.message or "unsaved_fork.gudsl:7:9" not in error.message:
        fail(f"the refusal names the fork's place: {error.message}")
    client.text_document_did_close(t.DidCloseTextDocumentParams(text_document=t.TextDocumentIdentifier(uri=fork_uri)))
    await wait_for(lambda: diagnostics.get(fork_uri) is not None and len(diagnostics[fork_uri]) == 0, "the closed unsaved document's diagnostics cleared")

    # Refusals: an unknown diagram, bad arguments, an unknown command.
    error = await refused(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.run", arguments=["Nope"])),
        "running an unknown diagram",
    )
    if "no activity diagram named `Nope`" not in error.message or "Main" not in error.message:
        fail(f"the refusal lists what can run: {error.message}")
    error = await refused(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.run", arguments=[42])),
        "bad arguments",
    )
    if "takes a diagram's name" not in error.message:
        fail(f"bad arguments: {error.message}")
    error = await refused(
        client.workspace_execute_command_async(t.ExecuteCommandParams(command="gudsl.nope")), "an unknown command"
    )
    if "gudsl.run" not in error.message:
        fail(f"unknown command: {error.message}")

    if gpu:
        await runs(client, out, progress, logs, shown, created)

    # A model with errors is refused, with the problems' places, and nothing runs.
    broken = main_text.replace("imageIndex = imageIndex + 1;", "imageIndex = imageIndx + 1;")
    client.text_document_did_open(
        t.DidOpenTextDocumentParams(text_document=t.TextDocumentItem(uri=main_uri, language_id="gudsl", version=1, text=broken))
    )
    await wait_for(lambda: diagnostics.get(main_uri), "the typo's diagnostic")
    refused_out = out / "refused"
    error = await refused(
        client.workspace_execute_command_async(
            t.ExecuteCommandParams(command="gudsl.run", arguments=[{"diagram": "Main", "output": str(refused_out)}])
        ),
        "running a model with errors",
    )
    if "the model has 1 error(s)" not in error.message or "imageIndx" not in error.message:
        fail(f"the refusal names the error: {error.message}")
    problems = (error.data or {}).get("problems", [])
    if [p["uri"] for p in problems] != [main_uri]:
        fail(f"the problems with their places expected as data: {error.data}")
    if refused_out.exists():
        fail("a refused run wrote output")

    await client.shutdown_async(None)
    client.exit(None)
    print("1 passed, 0 failed")


async def runs(client, out, progress, logs, shown, created):
    """Main runs to its end with progress (the client's token); a second run, without a token as
    a code lens sends it, reports under a token the server creates and is cancelled from it."""
    full = out / "full"
    started = time.monotonic()
    report = await client.workspace_execute_command_async(
        t.ExecuteCommandParams(
            command="gudsl.run", arguments=[{"diagram": "Main", "output": str(full)}], work_done_token="run-full"
        )
    )
    if not report["reached_final_node"] or report["error"] is not None:
        fail(f"Main did not run to its end: {report}")
    if sorted(p.name for p in full.iterdir()) != ["report.json"] + [f"viewer1-image{i}.png" for i in range(4)]:
        fail(f"the viewer's images and the report expected in {full}: {list(full.iterdir())}")
    if [c["node"] for c in report["calcs"]] != [
        "filterBilateralCL",
        "filterMean",
        "findIndexFirstStage",
        "findIndexSecondStage",
    ]:
        fail(f"the calc nodes' report: {report['calcs']}")
    values = progress.get("run-full", [])
    kinds = [field(v, "kind") for v in values]
    if kinds[0] != "begin" or kinds[-1] != "end" or "report" not in kinds:
        fail(f"progress begin, reports, end expected: {values}")
    if not field(values[0], "cancellable"):
        fail("the run's progress is not cancellable")
    if not any("node " in (field(v, "message") or "") for v in values):
        fail(f"nodes in the progress expected: {values}")
    if "to final node `f`" not in field(values[-1], "message"):
        fail(f"the end says how the run ended: {values[-1]}")
    if not any("first index of a value >= " in line for line in logs):
        fail(f"printf output as log messages expected: {logs}")
    if not any("ran Main to final node" in message for _, message in shown):
        fail(f"a message when the run ended expected: {shown}")
    full_seconds = time.monotonic() - started

    # Cancelled from the progress once the first node shows: it stops between nodes.
    cancelled_out = out / "cancelled"
    before = len(created)
    request = asyncio.ensure_future(
        client.workspace_execute_command_async(
            t.ExecuteCommandParams(command="gudsl.run", arguments=[{"diagram": "Main", "output": str(cancelled_out)}])
        )
    )
    token = await wait_for(lambda: created[before:] and created[-1], "a progress token created by the server", timeout=60.0)
    await wait_for(
        lambda: any(field(v, "kind") == "report" for v in progress.get(token, [])),
        "the second run's progress",
        timeout=60.0,
    )
    cancelled_at = time.monotonic()
    client.window_work_done_progress_cancel(t.WorkDoneProgressCancelParams(token=token))
    report = await request
    stopped_after = time.monotonic() - cancelled_at
    if report["reached_final_node"] or "cancelled" not in (report["error"] or ""):
        fail(f"the cancelled run should say so: {report}")
    if stopped_after > full_seconds / 2 + 0.5:
        fail(f"the run stopped {stopped_after:.2f} s after the cancel (a whole run takes {full_seconds:.2f} s)")
    if field(progress[token][-1], "kind") != "end":
        fail(f"the cancelled run's progress ends: {progress[token]}")
    if not (cancelled_out / "report.json").exists():
        fail("a cancelled run writes its report")

    # The command itself cancelled ($/cancelRequest, as a client does when the user gives up
    # waiting): the request is answered RequestCancelled, the run stops, its progress ends.
    dropped_out = out / "dropped"
    before = len(created)
    params = t.ExecuteCommandParams(command="gudsl.run", arguments=[{"diagram": "Main", "output": str(dropped_out)}])
    request = client.protocol.send_request_async("workspace/executeCommand", params, msg_id="run-dropped")
    dropped_token = await wait_for(lambda: created[before:] and created[-1], "the third run's token", timeout=60.0)
    await wait_for(
        lambda: any(field(v, "kind") == "report" for v in progress.get(dropped_token, [])),
        "the third run's progress",
        timeout=60.0,
    )
    client.protocol.notify("$/cancelRequest", t.CancelParams(id="run-dropped"))
    error = await refused(request, "a cancelled request")
    if error.code != -32800:
        fail(f"RequestCancelled expected: {error.code} {error.message}")
    ended = await wait_for(
        lambda: [v for v in progress[dropped_token] if field(v, "kind") == "end"], "the dropped run's progress end"
    )
    if field(ended[0], "message") != "cancelled":
        fail(f"the progress of a dropped run ends as cancelled: {ended}")
    report = json.loads(
        await wait_for(
            lambda: (dropped_out / "report.json").exists() and (dropped_out / "report.json").read_text(),
            "the dropped run's report",
        )
    )
    if report["reached_final_node"] or "cancelled" not in (report["error"] or ""):
        fail(f"the dropped run stops: {report}")
    print(f"whole run {full_seconds:.2f} s; stopped {stopped_after * 1000:.0f} ms after the cancel")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        fail("usage: run.py PATH_TO_GUDSL SAMPLES_DIR [--no-gpu]")
    asyncio.run(main(sys.argv[1], Path(sys.argv[2]).resolve(), "--no-gpu" not in sys.argv[3:]))
