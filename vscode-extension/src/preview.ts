//! The live preview in VS Code: the server's "◉ Live preview" lens turns it on and off
//! (`gudsl.preview`, sent by the language client as it is), and each `gudsl/preview` it sends
//! — a preview that ran, failed, or stopped on the model's errors — is shown in the results
//! panel, the newest only.
import * as vscode from 'vscode';
import { ExecuteCommandRequest } from 'vscode-languageclient/node';
import { Preview, previewNotification, PreviewState } from './protocol';
import { Report, showResults } from './results';
import { errorText, type Server } from './server';

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

/** "◉ Live preview" (the lens's `gudsl.preview`, taken over): turns the diagram's preview on or
 * off and says which pipeline is live in a message. */
export async function toggleLivePreview(server: Server, argument?: { diagram?: string }): Promise<PreviewState | undefined> {
  if (!argument?.diagram) return undefined;
  try {
    const client = await server.running();
    const state = (await client.sendRequest(ExecuteCommandRequest.type, {
      command: 'gudsl.preview',
      arguments: [{ diagram: argument.diagram, frames: vscode.workspace.getConfiguration('gudsl').get<number>('preview.frames', 1) }],
    })) as PreviewState;
    const said = state.live ? `live preview of ${state.diagram} on (its first ${state.frames} frame(s) run at each edit)` : 'live preview off';
    void vscode.window.setStatusBarMessage(`GU-DSL: ${said}`, 5000);
    return state;
  } catch (e) {
    void vscode.window.showErrorMessage(`GU-DSL: ${errorText(e)}`);
    return undefined;
  }
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
