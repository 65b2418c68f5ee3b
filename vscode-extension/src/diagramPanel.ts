//! The diagram panel: the diagram under the cursor as `gudsl/graph` draws it, redrawn when the
//! server says it changed (`gudsl/graphChanged`), selection synced both ways, and the webview's
//! gestures (drag, palette, context menu) sent as `gudsl/applyGraphEdit` operations — text edits
//! applied as the user's own (one undo each), moves written by the server into the layout sidecar.
import * as vscode from 'vscode';
import { LanguageClient, LSPErrorCodes, Range } from 'vscode-languageclient/node';
import { diagramsOf, innermostAt } from './diagrams';
import {
  applyGraphEditRequest,
  DiagramInfo,
  Graph,
  graphChangedNotification,
  graphRequest,
  GraphOperation,
  parametersRequest,
  setParameterRequest,
} from './protocol';
import { nonce } from './html';
import { errorText, Server } from './server';

/** What the webview sends. */
/** The diagram view's size in px. */
type Page = { width: number; height: number };

type FromView =
  | { type: 'ready'; page?: Page }
  | { type: 'page'; page: Page }
  | { type: 'select'; id: string; focus?: boolean }
  | { type: 'move'; id: string; x: number; y: number }
  | { type: 'unpin'; id: string }
  | { type: 'create'; kind: string; parent?: string }
  | { type: 'rename'; id: string }
  | { type: 'delete'; id: string }
  | { type: 'connect'; source: string; target: string }
  | { type: 'relayout'; page?: Page }
  | { type: 'setParameter'; instance: string; parameter: string; value: string };

/** The edge kinds a user connects two nodes of a class diagram by. */
const CLASS_RELATIONS = ['association', 'generalization', 'realization', 'aggregation', 'composition'];

export class DiagramPanel implements vscode.Disposable {
  private panel: vscode.WebviewPanel | undefined;
  private uri: string | undefined;
  private diagram: DiagramInfo | undefined;
  private graph: Graph | undefined;
  /** Counts graph requests: an answer older than the newest asked is dropped. */
  private generation = 0;
  private diagramsCache: { uri: string; version: number; diagrams: DiagramInfo[] } | undefined;
  private readonly disposables: vscode.Disposable[] = [];
  private staleTimer: NodeJS.Timeout | undefined;
  /** Counts cursor moves followed: a move's answer older than the newest is dropped. */
  private followed = 0;
  /** The pipeline instance whose parameters the panel shows. */
  private instance: string | undefined;
  /** The view's size, as the webview last said: fresh layouts are fitted to it. */
  private page: Page | undefined;

  constructor(
    private readonly server: Server,
    private readonly context: vscode.ExtensionContext,
  ) {
    server.onStarted((client) => {
      client.onNotification(graphChangedNotification, (changed) => {
        if (changed.uri === this.uri && this.diagram && changed.diagrams.includes(this.diagram.id)) void this.refresh();
      });
      if (this.panel) void this.follow(vscode.window.activeTextEditor, true);
    });
    this.disposables.push(
      vscode.window.onDidChangeTextEditorSelection((e) => void this.follow(e.textEditor)),
      vscode.window.onDidChangeActiveTextEditor((editor) => void this.follow(editor)),
      // An edit that only moves text sends no graphChanged, but it moves the ranges the panel
      // maps the cursor with and the version edits are made against: ask again once it settles.
      vscode.workspace.onDidChangeTextDocument((e) => {
        if (e.document.uri.toString() !== this.uri) return;
        clearTimeout(this.staleTimer);
        this.staleTimer = setTimeout(() => {
          if (this.graph && this.graph.version !== e.document.version) void this.refresh();
        }, 250);
      }),
    );
  }

  /** Opens the panel beside the editor (or brings it forward) on the diagram under the cursor. */
  async show(): Promise<void> {
    if (!this.panel) {
      const media = vscode.Uri.joinPath(this.context.extensionUri, 'media');
      this.panel = vscode.window.createWebviewPanel(
        'gudsl.diagram',
        'Diagram',
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        { enableScripts: true, retainContextWhenHidden: true, localResourceRoots: [media] },
      );
      this.panel.iconPath = vscode.Uri.joinPath(media, 'diagram.svg');
      this.panel.webview.html = this.html(this.panel.webview, media);
      this.panel.webview.onDidReceiveMessage((m: FromView) => void this.onMessage(m));
      this.panel.onDidDispose(() => {
        this.panel = undefined;
        this.uri = undefined;
        this.diagram = undefined;
        this.graph = undefined;
      });
    } else {
      this.panel.reveal(undefined, true);
    }
    const editor = vscode.window.activeTextEditor ?? vscode.window.visibleTextEditors.find((e) => e.document.languageId === 'gudsl');
    await this.follow(editor, true);
  }

  /** Shows the diagram under `editor`'s cursor and highlights the element the cursor is in. */
  private async follow(editor: vscode.TextEditor | undefined, force = false): Promise<void> {
    if (!this.panel || !editor || editor.document.languageId !== 'gudsl') return;
    let client: LanguageClient;
    try {
      client = await this.server.running();
    } catch {
      return;
    }
    const document = editor.document;
    const uri = document.uri.toString();
    const followed = ++this.followed;
    let diagrams: DiagramInfo[];
    if (this.diagramsCache?.uri === uri && this.diagramsCache.version === document.version) {
      diagrams = this.diagramsCache.diagrams;
    } else {
      try {
        diagrams = await diagramsOf(client, document);
      } catch {
        return; // an edit or a restart came between: the next cursor move asks again
      }
      this.diagramsCache = { uri, version: document.version, diagrams };
    }
    if (followed !== this.followed) return;
    const position = editor.selection.active;
    const here = innermostAt(diagrams, position) ?? (uri === this.uri ? undefined : diagrams[0]);
    if (here && (force || uri !== this.uri || here.id !== this.diagram?.id)) {
      this.uri = uri;
      this.diagram = here;
      await this.refresh();
    } else if (force && !here) {
      this.post({ type: 'message', text: `${vscode.workspace.asRelativePath(document.uri)} declares no diagram` });
    }
    if (uri === this.uri) {
      // On a declaration's line, before its first word, the cursor still means that declaration.
      const indent = document.lineAt(position.line).firstNonWhitespaceCharacterIndex;
      const id = this.elementAt(position) ?? this.elementAt(position.with(undefined, Math.max(position.character, indent)));
      this.post({ type: 'highlight', id: id ?? null });
      await this.showParameters(id);
    }
  }

  /** The parameters of the instance `id` names (a pipeline's), as controls beside the diagram;
   * none for anything else. */
  private async showParameters(id: string | undefined): Promise<void> {
    const node = this.graph?.diagram.kind === 'componentInstance' ? this.graph.nodes.find((n) => n.id === id) : undefined;
    this.instance = node?.shape === 'instance' ? node.id : undefined;
    if (!this.instance || !this.uri || !this.diagram) return this.post({ type: 'parameters', parameters: null });
    try {
      const client = await this.server.running();
      const shown = await client.sendRequest(parametersRequest, { textDocument: { uri: this.uri }, diagram: this.diagram.id, instance: this.instance });
      if (shown.instance === this.instance) this.post({ type: 'parameters', ...shown });
    } catch {
      this.post({ type: 'parameters', parameters: null }); // an edit came between: the next selection asks again
    }
  }

  /** A control's value written into the text (one undo), as `gudsl/setParameter` edits it. */
  private async setParameter(instance: string, parameter: string, value: string): Promise<void> {
    const uri = this.uri!;
    try {
      const client = await this.server.running();
      const open = vscode.workspace.textDocuments.find((d) => d.uri.toString() === uri);
      const answer = await client.sendRequest(setParameterRequest, {
        textDocument: { uri, version: open?.version ?? null },
        diagram: this.diagram!.id,
        instance,
        parameter,
        value,
      });
      const edit = await client.protocol2CodeConverter.asWorkspaceEdit(answer);
      if (edit.size > 0 && !(await vscode.workspace.applyEdit(edit))) {
        void vscode.window.showErrorMessage('GU-DSL: the editor did not apply the parameter (the document changed meanwhile?)');
      }
    } catch (e) {
      void vscode.window.showErrorMessage(`GU-DSL: ${instance}.${parameter} = ${value}: ${errorText(e)}`);
    }
  }

  /** The id of the innermost node or edge whose text holds `position`. */
  private elementAt(position: vscode.Position): string | undefined {
    return innermostAt<{ id: string; range: Range }>([...(this.graph?.nodes ?? []), ...(this.graph?.edges ?? [])], position)?.id;
  }

  /** Asks for the shown diagram again and sends it to the webview. */
  private async refresh(relayout = false): Promise<void> {
    const uri = this.uri;
    const diagram = this.diagram;
    if (!this.panel || !uri || !diagram) return;
    const generation = ++this.generation;
    let client: LanguageClient;
    try {
      client = await this.server.running();
    } catch (e) {
      this.post({ type: 'message', text: errorText(e) });
      return;
    }
    for (let attempt = 0; attempt < 5; attempt++) {
      try {
        const graph = await client.sendRequest(graphRequest, { textDocument: { uri }, diagram: diagram.id, svg: true, relayout, page: this.page });
        if (generation !== this.generation) return;
        this.graph = graph;
        this.panel.title = `Diagram: ${graph.diagram.name}`;
        this.post({
          type: 'graph',
          kind: graph.diagram.kind,
          name: graph.diagram.name,
          version: graph.version,
          svg: graph.svg,
          nodes: graph.nodes.map((n) => ({ id: n.id, label: n.label, shape: n.shape, bounds: n.bounds, pinned: n.pinned, parent: n.parent, group: n.group })),
          groups: graph.groups.map((g) => g.id),
          layoutError: graph.layoutError,
        });
        if (this.instance) await this.showParameters(this.instance);
        return;
      } catch (e) {
        if ((e as { code?: number }).code === LSPErrorCodes.ContentModified) {
          await new Promise((resolve) => setTimeout(resolve, 50 * (attempt + 1)));
          if (generation !== this.generation) return;
          continue;
        }
        if (generation !== this.generation) return;
        // The diagram is gone (renamed, deleted): show the one the document now has there.
        const document = vscode.workspace.textDocuments.find((d) => d.uri.toString() === uri);
        const diagrams = document ? await diagramsOf(client, document).catch(() => []) : [];
        const again = diagrams.find((d) => d.id === diagram.id) ? undefined : diagrams.find((d) => d.name === diagram.name) ?? diagrams[0];
        if (generation !== this.generation || uri !== this.uri) return;
        if (again && again.id !== diagram.id) {
          this.diagram = again;
          return this.refresh(relayout);
        }
        this.post({ type: 'message', text: errorText(e) });
        return;
      }
    }
    this.post({ type: 'message', text: 'the diagram kept changing while it was drawn; edit again to redraw it' });
  }

  private async onMessage(message: FromView): Promise<void> {
    const graph = this.graph;
    if (message.type === 'ready' || message.type === 'page') {
      this.page = message.page ?? this.page;
      if (graph && message.type === 'ready') await this.refresh();
      return;
    }
    if (!graph || !this.uri || !this.diagram) return;
    switch (message.type) {
      case 'select':
        await this.showParameters(message.id);
        return this.reveal(message.id, message.focus ?? false);
      case 'setParameter':
        return this.setParameter(message.instance, message.parameter, message.value);
      case 'move':
        return this.edit([{ op: 'move', element: message.id, position: { x: Math.max(0, message.x), y: Math.max(0, message.y) } }]);
      case 'unpin':
        return this.edit([{ op: 'move', element: message.id, position: null }]);
      case 'relayout':
        this.page = message.page ?? this.page;
        return this.refresh(true);
      case 'delete':
        return this.edit([{ op: 'delete', element: message.id }]);
      case 'rename': {
        const node = graph.nodes.find((n) => n.id === message.id);
        const current = node?.label.split(/\s*:\s*/)[0] ?? message.id.split(/[./]/).pop() ?? '';
        const name = await askName(`New name of ${current}`, current);
        if (name && name !== current) await this.edit([{ op: 'rename', element: message.id, name }]);
        return;
      }
      case 'create': {
        const name = await askName(`Name of the new ${message.kind}`, defaultName(message.kind, graph), message.kind === 'component');
        if (!name) return;
        const operation: GraphOperation = { op: 'create', kind: message.kind, name };
        if (message.parent) operation.parent = message.parent;
        if (message.kind === 'instance') {
          const component = await vscode.window.showInputBox({ prompt: `Component class of ${name}`, placeHolder: 'e.g. ToF.MedianFilter' });
          if (!component) return;
          operation.properties = { component };
        }
        return this.edit([operation]);
      }
      case 'connect': {
        const kind = {
          activity: 'transition',
          component: 'connection',
          componentInstance: 'binding',
          class: undefined,
        }[graph.diagram.kind] ?? (await vscode.window.showQuickPick(CLASS_RELATIONS, { placeHolder: 'Which relation?' }));
        if (!kind) return;
        return this.edit([{ op: 'connect', kind, source: message.source, target: message.target }]);
      }
    }
  }

  /** Sends `operations` for the graph shown, and applies the text edits of the answer. */
  private async edit(operations: GraphOperation[]): Promise<void> {
    const uri = this.uri!;
    try {
      const client = await this.server.running();
      // Ids outlive edits, versions do not: edit the document as it is now.
      const open = vscode.workspace.textDocuments.find((d) => d.uri.toString() === uri);
      if (open && this.graph && open.version !== this.graph.version) await this.refresh();
      const answer = await client.sendRequest(applyGraphEditRequest, {
        textDocument: { uri, version: this.graph?.version ?? null },
        diagram: this.diagram!.id,
        operations,
      });
      const edit = await client.protocol2CodeConverter.asWorkspaceEdit(answer.edit);
      if (edit.size > 0 && !(await vscode.workspace.applyEdit(edit))) {
        void vscode.window.showErrorMessage('GU-DSL: the editor did not apply the diagram edit (the document changed meanwhile?)');
      }
    } catch (e) {
      void vscode.window.showErrorMessage(`GU-DSL: ${errorText(e)}`);
      await this.refresh();
    }
  }

  /** Puts the cursor on the declaration of `id` (a node, an edge, or a port's node) in the editor
   * of the shown document; `focus` moves the keyboard there too (else it stays in the panel, where
   * Del and F2 act on the selection). */
  private async reveal(id: string, focus: boolean): Promise<void> {
    const elements = [...(this.graph?.nodes ?? []), ...(this.graph?.edges ?? [])];
    const element = elements.find((e) => e.id === id) ?? this.graph?.nodes.find((n) => n.ports.some((p) => p.id === id));
    if (!element || !this.uri) return;
    const uri = vscode.Uri.parse(this.uri);
    const visible = vscode.window.visibleTextEditors.find((e) => e.document.uri.toString() === this.uri);
    const position = new vscode.Position(element.range.start.line, element.range.start.character);
    try {
      const editor = await vscode.window.showTextDocument(uri, {
        viewColumn: visible?.viewColumn ?? vscode.ViewColumn.One,
        selection: new vscode.Range(position, position),
        preserveFocus: !focus,
      });
      editor.revealRange(new vscode.Range(position, position), vscode.TextEditorRevealType.InCenterIfOutsideViewport);
    } catch (e) {
      void vscode.window.showErrorMessage(`GU-DSL: cannot show ${id}: ${errorText(e)}`);
    }
  }

  private post(message: unknown): void {
    void this.panel?.webview.postMessage(message);
  }

  private html(webview: vscode.Webview, media: vscode.Uri): string {
    const n = nonce();
    const script = webview.asWebviewUri(vscode.Uri.joinPath(media, 'diagram.js'));
    const style = webview.asWebviewUri(vscode.Uri.joinPath(media, 'diagram.css'));
    return `<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; img-src ${webview.cspSource} data:; style-src ${webview.cspSource}; script-src 'nonce-${n}';">
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="stylesheet" href="${style}"><title>Diagram</title></head>
<body><div id="toolbar" role="toolbar" aria-label="Diagram palette"></div><div id="status" role="status"></div>
<div id="canvas" tabindex="0"></div><div id="params" role="form" aria-label="Parameters" hidden></div><div id="menu" role="menu" hidden></div>
<script nonce="${n}" src="${script}"></script></body></html>`;
  }

  dispose(): void {
    clearTimeout(this.staleTimer);
    this.panel?.dispose();
    for (const d of this.disposables) d.dispose();
  }
}

/** Asks for a name (an identifier, as GU-DSL takes it; `qualified`: `Diagram.Class` too, as a
 * component is named by its class). */
function askName(prompt: string, value: string, qualified = false): Thenable<string | undefined> {
  const pattern = qualified ? /^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$/ : /^[A-Za-z_]\w*$/;
  return vscode.window.showInputBox({
    prompt,
    value,
    validateInput: (text) =>
      pattern.test(text) ? undefined : `a name: letters, digits and _, not starting with a digit${qualified ? ' (qualified with dots)' : ''}`,
  });
}

/** A name for a new element that the diagram does not have yet: `action1`, `Class2`, … */
function defaultName(kind: string, graph: Graph): string {
  const base = ['class', 'interface', 'enum', 'component', 'instance'].includes(kind) ? kind[0].toUpperCase() + kind.slice(1) : kind;
  const taken = new Set(graph.nodes.map((n) => n.id.split(/[./]/).pop()));
  for (let i = 1; ; i++) if (!taken.has(`${base}${i}`)) return `${base}${i}`;
}
