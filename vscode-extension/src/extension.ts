//! The GU-DSL extension's entry: starts `gudsl lsp`, restarts it when its settings change or the
//! workspace is trusted, and registers the commands, the status bar item, the diagram panel and
//! the runs.
import * as vscode from 'vscode';
import { DiagramPanel } from './diagramPanel';
import { followPreviews, toggleLivePreview } from './preview';
import { renderDiagram } from './render';
import { RunArgument, Runs } from './runs';
import { Server } from './server';
import { StatusItem } from './status';
import { WgslDocuments } from './wgsl';

let server: Server | undefined;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const started = Date.now();
  const output = vscode.window.createOutputChannel('GU-DSL Language Server', { log: true });
  const status = new StatusItem();
  server = new Server(context, output, status);
  const runs = new Runs(server, status, context);
  const panel = new DiagramPanel(server, context);
  const wgsl = new WgslDocuments(server);
  followPreviews(server, context);
  context.subscriptions.push(
    output,
    status,
    panel,
    vscode.workspace.registerTextDocumentContentProvider('gudsl', wgsl),
    vscode.commands.registerCommand('gudsl.restartServer', () => server!.restart()),
    vscode.commands.registerCommand('gudsl.showServerLog', () => output.show(true)),
    vscode.commands.registerCommand('gudsl.showDiagram', () => panel.show()),
    vscode.commands.registerCommand('gudsl.renderDiagram', () => renderDiagram(server!)),
    vscode.commands.registerCommand('gudsl.runDiagram', (arg?: RunArgument) => runs.run(arg)),
    vscode.commands.registerCommand('gudsl.showGeneratedWgsl', (arg?: { diagram?: string }) => wgsl.show(arg?.diagram)),
    vscode.commands.registerCommand('gudsl.toggleLivePreview', (arg?: { diagram?: string }) => toggleLivePreview(server!, arg)),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('gudsl.server')) void server!.restart();
    }),
    // The server learns trust at start (`initializationOptions.trusted`).
    vscode.workspace.onDidGrantWorkspaceTrust(() => void server!.restart()),
  );
  await server.start();
  output.info(`extension activated in ${Date.now() - started} ms, language server started and initialized (server: ${server.binary?.command}, from ${server.binary?.origin})`);
}

export function deactivate(): Promise<void> | undefined {
  return server?.stop();
}
