//! gudsl's requests beyond LSP (`docs/protocol.md`), typed for the client; the server's side is
//! `server/src/lsp/ext.rs` (its commands: `gudsl.run`, `gudsl.runPipeline`, `gudsl.showWgsl`,
//! `gudsl.preview`).
//! lsp/ext.rs hash: b040a20f21dab895 (a test checks this file is reviewed whenever ext.rs changes)
import { NotificationType, Range, RequestType, TextDocumentIdentifier, VersionedTextDocumentIdentifier, WorkspaceEdit } from 'vscode-languageclient';

export type DiagramKind = 'class' | 'activity' | 'component' | 'componentInstance';

export interface DiagramInfo {
  id: string;
  name: string;
  kind: DiagramKind;
  range: Range;
  selectionRange: Range;
}

export interface Diagrams {
  uri: string;
  version: number | null;
  diagrams: DiagramInfo[];
}

export interface Bounds {
  x: number;
  y: number;
  width: number;
  height: number;
}

export interface GraphNode {
  id: string;
  shape: string;
  label: string;
  range: Range;
  bounds: Bounds | null;
  pinned: boolean;
  group: string | null;
  parent: string | null;
  ports: { id: string; label: string; provider: boolean | null }[];
}

export interface GraphEdge {
  id: string;
  kind: string;
  source: { node: string; port: string | null };
  target: { node: string; port: string | null };
  label: string | null;
  range: Range;
}

export interface Graph {
  uri: string;
  version: number | null;
  diagram: DiagramInfo;
  width: number;
  height: number;
  nodes: GraphNode[];
  edges: GraphEdge[];
  groups: { id: string; label: string; owner: string | null; bounds: Bounds | null }[];
  svg?: string;
  png?: string;
  layoutError?: string;
}

/** One operation of `gudsl/applyGraphEdit`. */
export type GraphOperation = { op: string } & Record<string, unknown>;

export interface GraphEditResult {
  edit: WorkspaceEdit;
  layout?: { uri: string; diagram: string };
}

export const diagramsRequest = new RequestType<{ textDocument: TextDocumentIdentifier }, Diagrams | null, void>('gudsl/diagrams');

export const graphRequest = new RequestType<
  {
    textDocument: TextDocumentIdentifier;
    diagram: string;
    svg?: boolean;
    png?: boolean;
    relayout?: boolean;
    /** The diagram view's size in px: a fresh layout is fitted to its shape. */
    page?: { width: number; height: number };
  },
  Graph,
  void
>('gudsl/graph');

export const applyGraphEditRequest = new RequestType<
  { textDocument: { uri: string; version: number | null }; diagram: string; operations: GraphOperation[] },
  GraphEditResult,
  void
>('gudsl/applyGraphEdit');

export const viewFileTextRequest = new RequestType<TextDocumentIdentifier, string | null, void>('gudsl/viewFileText');

export const graphChangedNotification = new NotificationType<{ uri: string; version: number | null; diagrams: string[] }>('gudsl/graphChanged');

export type { VersionedTextDocumentIdentifier };

/** The answer of `gudsl.preview`: which pipeline is live now. */
export interface PreviewState {
  diagram: string | null;
  live: boolean;
  frames: number;
}

/** `gudsl/preview`: a live preview ran (`ran`, `failed`) or stopped on the model's errors. */
export interface Preview {
  diagram: string;
  uri: string | null;
  version: number | null;
  sequence: number;
  state: 'ran' | 'failed' | 'stopped';
  message: string;
  report: { frames: number; stages: unknown[]; figures: { stage: string; name: string; value: number }[]; outputs: string[] } | null;
  replayed: string[];
  problems: unknown[];
  output: string | null;
  timings: { prepareMs: number; queuedMs: number; runMs: number; totalMs: number };
}

export const previewNotification = new NotificationType<Preview>('gudsl/preview');

/** One parameter of an instance (`gudsl/parameters`): its declared type, range and value. */
export interface ParameterView {
  name: string;
  type: string;
  value: string | null;
  written: boolean;
  min: number | null;
  max: number | null;
  step: number | null;
  choices: string[];
  inputFile: boolean;
}

export interface Parameters {
  uri: string;
  version: number | null;
  instance: string;
  component: string;
  parameters: ParameterView[];
}

export const parametersRequest = new RequestType<{ textDocument: TextDocumentIdentifier; diagram: string; instance: string }, Parameters, void>('gudsl/parameters');
export const setParameterRequest = new RequestType<
  { textDocument: { uri: string; version: number | null }; diagram: string; instance: string; parameter: string; value: string },
  WorkspaceEdit,
  void
>('gudsl/setParameter');
