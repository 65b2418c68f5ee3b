//! Which diagram a command is about: the one under the cursor in the active GU-DSL editor, else
//! the user's pick among the document's diagrams (`gudsl/diagrams`).
import * as vscode from 'vscode';
import type { LanguageClient, Range } from 'vscode-languageclient/node';
import { DiagramInfo, DiagramKind, diagramsRequest } from './protocol';

/** A document's diagrams, in the order written (empty for a document the server does not know). */
export async function diagramsOf(client: LanguageClient, document: vscode.TextDocument): Promise<DiagramInfo[]> {
  const answer = await client.sendRequest(diagramsRequest, { textDocument: { uri: document.uri.toString() } });
  return answer?.diagrams ?? [];
}

/** An LSP range as VS Code's. */
export function vscodeRange(r: Range): vscode.Range {
  return new vscode.Range(r.start.line, r.start.character, r.end.line, r.end.character);
}

/** The innermost of `items` (diagrams, nodes, edges) whose text holds `position`. */
export function innermostAt<T extends { range: Range }>(items: T[], position: vscode.Position): T | undefined {
  let best: { item: T; size: number } | undefined;
  for (const item of items) {
    const r = item.range;
    if (!vscodeRange(r).contains(position)) continue;
    const size = (r.end.line - r.start.line) * 10000 + (r.end.character - r.start.character);
    if (!best || size < best.size) best = { item, size };
  }
  return best?.item;
}

/** The diagram a command acts on: `kinds` limits which; undefined when the user cancelled. */
export async function chooseDiagram(
  client: LanguageClient,
  kinds?: DiagramKind[],
): Promise<{ document: vscode.TextDocument; diagram: DiagramInfo } | undefined> {
  const editor = vscode.window.activeTextEditor;
  if (!editor || editor.document.languageId !== 'gudsl') {
    void vscode.window.showErrorMessage('GU-DSL: open a .gudsl document first');
    return undefined;
  }
  const diagrams = (await diagramsOf(client, editor.document)).filter((d) => !kinds || kinds.includes(d.kind));
  if (diagrams.length === 0) {
    const what = kinds ? kinds.map(kindName).join(' or ') + ' diagram' : 'diagram';
    void vscode.window.showErrorMessage(`GU-DSL: ${vscode.workspace.asRelativePath(editor.document.uri)} declares no ${what}`);
    return undefined;
  }
  const here = innermostAt(diagrams, editor.selection.active);
  if (here) return { document: editor.document, diagram: here };
  if (diagrams.length === 1) return { document: editor.document, diagram: diagrams[0] };
  const pick = await vscode.window.showQuickPick(
    diagrams.map((d) => ({ label: d.name, description: `${kindName(d.kind)} diagram`, detail: d.id !== d.name ? d.id : undefined, diagram: d })),
    { placeHolder: 'Which diagram?' },
  );
  return pick && { document: editor.document, diagram: pick.diagram };
}

export function kindName(kind: DiagramKind): string {
  return kind === 'componentInstance' ? 'component-instance' : kind;
}
