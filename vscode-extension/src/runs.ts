//! "Run Pipeline / Run Diagram" and the ▶ code lenses: `gudsl.runPipeline` or `gudsl.run` sent
//! with the extension's own progress token, shown as a notification with a cancel button (cancel
//! sends `$/cancelRequest`, which stops the run between frames or nodes), then the results panel.
import * as path from 'node:path';
import * as vscode from 'vscode';
import { ExecuteCommandRequest, LSPErrorCodes, WorkDoneProgress, WorkDoneProgressBegin, WorkDoneProgressEnd, WorkDoneProgressReport } from 'vscode-languageclient/node';
import { chooseDiagram } from './diagrams';
import { Report, showResults } from './results';
import { errorText, Server, settingPath } from './server';
import type { StatusItem } from './status';

/** What a code lens or a caller passes: the diagram and the server's command. */
export interface RunArgument {
  diagram?: string;
  /** `gudsl.runPipeline` or `gudsl.run`, as the lens named it. */
  serverCommand?: string;
}

export class Runs {
  private next = 0;
  private running = 0;

  constructor(
    private readonly server: Server,
    private readonly status: StatusItem,
    private readonly context: vscode.ExtensionContext,
  ) {}

  async run(argument?: RunArgument): Promise<Report | undefined> {
    let client;
    try {
      client = await this.server.running();
    } catch (e) {
      void vscode.window.showErrorMessage(`GU-DSL: ${errorText(e)}`);
      return undefined;
    }
    let diagram = argument?.diagram;
    let command = argument?.serverCommand;
    if (!diagram) {
      const chosen = await chooseDiagram(client, ['activity', 'componentInstance']);
      if (!chosen) return undefined;
      diagram = chosen.diagram.id;
      command = chosen.diagram.kind === 'componentInstance' ? 'gudsl.runPipeline' : 'gudsl.run';
    }
    command ??= 'gudsl.run';
    const name = diagram;
    const args: Record<string, unknown> = { diagram };
    const folder = outputFolder();
    if (folder) args.output = path.join(folder, diagram.replace(/[^A-Za-z0-9_.-]/g, '_'));

    const token = `gudsl-vscode/run/${++this.next}`;
    this.running++;
    this.status.working(`Running ${name}`);
    try {
      return await vscode.window.withProgress(
        { location: vscode.ProgressLocation.Notification, title: `Running ${name}`, cancellable: true },
        async (progress, cancelled) => {
          let done = 0;
          const listener = client.onProgress(WorkDoneProgress.type, token, (value) => {
            const step = value as WorkDoneProgressBegin | WorkDoneProgressReport | WorkDoneProgressEnd;
            if (step.kind === 'end') return;
            const increment = step.percentage !== undefined ? Math.max(0, step.percentage - done) : undefined;
            if (step.percentage !== undefined) done = Math.max(done, step.percentage);
            progress.report({ message: step.message, increment });
            if (step.message) this.status.working(`${name}: ${step.message}`);
          });
          try {
            const answer = (await client.sendRequest(
              ExecuteCommandRequest.type,
              { command: command!, arguments: [args], workDoneToken: token },
              cancelled,
            )) as Report;
            showResults(this.context, answer);
            return answer;
          } catch (e) {
            const code = (e as { code?: number }).code;
            if (cancelled.isCancellationRequested || code === LSPErrorCodes.RequestCancelled) {
              void vscode.window.showInformationMessage(`GU-DSL: ${name}: run cancelled`);
            } else if (code !== LSPErrorCodes.RequestFailed) {
              // (RequestFailed: the server refused and has shown the user why.)
              void vscode.window.showErrorMessage(`GU-DSL: ${name} did not run: ${errorText(e)}`);
            }
            return undefined;
          } finally {
            listener.dispose();
          }
        },
      );
    } finally {
      if (--this.running === 0) this.status.working(undefined);
    }
  }
}

/** `gudsl.run.outputFolder` as an absolute path, or undefined for the server's default. */
function outputFolder(): string | undefined {
  const configured = vscode.workspace.getConfiguration('gudsl').get<string | null>('run.outputFolder')?.trim();
  return configured ? settingPath(configured) : undefined;
}
