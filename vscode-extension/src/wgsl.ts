//! "Show Generated WGSL": the WGSL of a device diagram as a read-only document
//! (`gudsl:/wgsl/<diagram>.wgsl`, served by `gudsl/viewFileText`), regenerated as the model changes.
import * as vscode from 'vscode';
import { ExecuteCommandRequest } from 'vscode-languageclient/node';
import { chooseDiagram } from './diagrams';
import { viewFileTextRequest } from './protocol';
import { errorText, Server } from './server';

export class WgslDocuments implements vscode.TextDocumentContentProvider, vscode.Disposable {
  private readonly changed = new vscode.EventEmitter<vscode.Uri>();
  readonly onDidChange = this.changed.event;
  private readonly subscription: vscode.Disposable;
  private timer: NodeJS.Timeout | undefined;

  constructor(private readonly server: Server) {
    // The generated text follows the model: after an edit of any GU-DSL document, the open
    // generated documents are read again (once for a burst of keystrokes).
    this.subscription = vscode.workspace.onDidChangeTextDocument((e) => {
      if (e.document.languageId !== 'gudsl') return;
      clearTimeout(this.timer);
      this.timer = setTimeout(() => {
        for (const doc of vscode.workspace.textDocuments) if (doc.uri.scheme === 'gudsl') this.changed.fire(doc.uri);
      }, 300);
    });
  }

  async provideTextDocumentContent(uri: vscode.Uri): Promise<string> {
    try {
      const client = await this.server.running();
      return (await client.sendRequest(viewFileTextRequest, { uri: uri.toString() })) ?? `// ${uri.toString()}: no such generated document\n`;
    } catch (e) {
      return `// ${errorText(e)}\n`;
    }
  }

  /** Opens the WGSL of `diagram`, or of the device diagram under the cursor. */
  async show(diagram?: string): Promise<void> {
    try {
      const client = await this.server.running();
      if (!diagram) {
        const chosen = await chooseDiagram(client, ['activity']);
        if (!chosen) return;
        diagram = chosen.diagram.id;
      }
      const answer = (await client.sendRequest(ExecuteCommandRequest.type, { command: 'gudsl.showWgsl', arguments: [{ diagram }] })) as { uri: string };
      const document = await vscode.workspace.openTextDocument(vscode.Uri.parse(answer.uri));
      await vscode.languages.setTextDocumentLanguage(document, 'wgsl').then(undefined, () => undefined);
      await vscode.window.showTextDocument(document, { viewColumn: vscode.ViewColumn.Beside, preview: true });
    } catch (e) {
      void vscode.window.showErrorMessage(`GU-DSL: no WGSL: ${errorText(e)}`);
    }
  }

  dispose(): void {
    clearTimeout(this.timer);
    this.subscription.dispose();
    this.changed.dispose();
  }
}
