//! The live preview in VS Code: the server's "◉ Live preview" lens turns it on and off
//! (`gudsl.preview`, sent by the language client as it is), and each `gudsl/preview` it sends
//! — a preview that ran, failed, or stopped on the model's errors — is shown in the results
//! panel, the newest only.
import * as vscode from 'vscode';
import { Preview, previewNotification } from './protocol';
import { Report, showResults } from './results';
import type { Server } from './server';

export function followPreviews(server: Server, context: vscode.ExtensionContext): void {
  let newest = 0;
  server.onStarted((client) => {
    newest = 0;
    context.subscriptions.push(
      client.onNotification(previewNotification, (preview) => {
        if (preview.sequence <= newest) return;
        newest = preview.sequence;
        showResults(context, previewReport(preview));
      }),
    );
  });
}

/** A preview as the results panel shows a run. */
export function previewReport(preview: Preview): Report {
  const t = preview.timings;
  const replayed = preview.replayed.length ? `; replayed: ${preview.replayed.join(', ')}` : '';
  const where = (preview.problems[0] as { location?: Report['errorLocation'] } | undefined)?.location;
  return {
    ...(preview.report ?? {}),
    diagram: `${preview.diagram} (live)`,
    output: preview.output ?? undefined,
    error: preview.state === 'ran' ? null : preview.message,
    errorLocation: where ?? null,
    note: `live preview ${preview.sequence}: ${t.totalMs.toFixed(0)} ms from the edit (prepare ${t.prepareMs.toFixed(0)}, run ${t.runMs.toFixed(0)})${replayed}`,
    revision: preview.sequence,
  } as Report;
}
