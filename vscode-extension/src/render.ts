//! "Render Diagram to SVG/PNG…": the diagram under the cursor, as the editor has it now (unsaved
//! edits included), drawn by the server as `gudsl render` draws it, saved where the user says.
import * as path from 'node:path';
import * as vscode from 'vscode';
import { chooseDiagram } from './diagrams';
import { graphRequest } from './protocol';
import { errorText, Server } from './server';

export async function renderDiagram(server: Server): Promise<void> {
  try {
    const client = await server.running();
    const chosen = await chooseDiagram(client);
    if (!chosen) return;
    const format = await vscode.window.showQuickPick(
      [
        { label: 'SVG', description: 'vector, as `gudsl render --format svg`', ext: 'svg' },
        { label: 'PNG', description: 'raster at twice the size, as `gudsl render --format png`', ext: 'png' },
      ],
      { placeHolder: `Render ${chosen.diagram.name} as` },
    );
    if (!format) return;
    const folder = chosen.document.uri.scheme === 'file' ? path.dirname(chosen.document.uri.fsPath) : vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
    const target = await vscode.window.showSaveDialog({
      defaultUri: folder ? vscode.Uri.file(path.join(folder, `${chosen.diagram.name}.${format.ext}`)) : undefined,
      filters: { [format.label]: [format.ext] },
      title: `Render ${chosen.diagram.name} to ${format.label}`,
    });
    if (!target) return;
    const graph = await client.sendRequest(graphRequest, {
      textDocument: { uri: chosen.document.uri.toString() },
      diagram: chosen.diagram.id,
      svg: format.ext === 'svg',
      png: format.ext === 'png',
    });
    const bytes = format.ext === 'svg' ? Buffer.from(graph.svg ?? '', 'utf8') : Buffer.from(graph.png ?? '', 'base64');
    await vscode.workspace.fs.writeFile(target, bytes);
    const open = 'Open';
    const choice = await vscode.window.showInformationMessage(`GU-DSL: wrote ${vscode.workspace.asRelativePath(target)} (${bytes.length} bytes)`, open);
    if (choice === open) await vscode.commands.executeCommand('vscode.open', target);
  } catch (e) {
    void vscode.window.showErrorMessage(`GU-DSL: could not render: ${errorText(e)}`);
  }
}
