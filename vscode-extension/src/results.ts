//! The results panel of a run: what ran where and how long, the stages' or kernels' table, the
//! error with a link to its place, the plots and images inline, the arrays it wrote to inspect
//! (`media/inspect.js`: colour map, value under the cursor, A − B), its point clouds in 3D
//! (`media/cloud.js`: orbit, zoom, colour by depth or height), and every output file to open.
import * as path from 'node:path';
import * as vscode from 'vscode';
import { escapeHtml, nonce } from './html';

/** The answer of `gudsl.run` / `gudsl.runPipeline`: `report.json` plus `output`, `table`, `errorLocation`. */
export interface Report {
  diagram?: string;
  device?: string;
  output?: string;
  error?: string | null;
  total_ms?: number;
  frames?: number;
  table?: string;
  outputs?: string[];
  plots?: string[];
  images?: string[];
  printed?: string[];
  calcs?: { node: string; kernel: string; launches: number; device_ms: number; wall_ms: number }[];
  errorLocation?: { uri: string; range: { start: { line: number; character: number } } } | null;
  /** What the stages measured (an accuracy report's errors). */
  figures?: { stage: string; name: string; value: number }[];
  /** A line under the summary (a live preview's timings and replayed stages). */
  note?: string;
  /** Bumped by every live preview: its pictures, rewritten under the same names, are reloaded. */
  revision?: number;
}

/** How many images the panel shows inline (the rest are listed). */
const INLINE_IMAGES = 12;

let panel: vscode.WebviewPanel | undefined;
/** The report the panel shows (its error's place is where "Go to the place" goes). */
let shown: Report | undefined;

export function showResults(context: vscode.ExtensionContext, report: Report): void {
  const output = report.output ?? '';
  const files = (report.outputs ?? (report.images ?? []).map((name) => path.join(output, name))).map((f) =>
    path.isAbsolute(f) ? f : path.join(output, f),
  );
  // The pictures are read from the run's folder only (none when the answer names none).
  const media = vscode.Uri.joinPath(context.extensionUri, 'media');
  const roots = output ? [vscode.Uri.file(output), media] : [media];
  if (!panel) {
    panel = vscode.window.createWebviewPanel('gudsl.results', 'Run results', { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true }, {
      enableScripts: true,
      localResourceRoots: roots,
    });
    panel.onDidDispose(() => (panel = undefined), undefined, context.subscriptions);
    panel.webview.onDidReceiveMessage((message: { open?: string; location?: boolean }) => {
      if (message.open) void vscode.commands.executeCommand('vscode.open', vscode.Uri.file(message.open), vscode.ViewColumn.One);
      const at = shown?.errorLocation;
      if (message.location && at) {
        const position = new vscode.Position(at.range.start.line, at.range.start.character);
        void vscode.window.showTextDocument(vscode.Uri.parse(at.uri), { selection: new vscode.Range(position, position), viewColumn: vscode.ViewColumn.One });
      }
    }, undefined, context.subscriptions);
  } else {
    panel.webview.options = { enableScripts: true, localResourceRoots: roots };
    panel.reveal(undefined, true);
  }
  shown = report;
  const current = panel;
  current.title = `Run: ${report.diagram ?? 'results'}`;
  current.webview.html = resultsHtml(current.webview, report, files, media);
}

/** How many arrays the inspector offers (the first ones written). */
const INSPECTED_ARRAYS = 200;

function resultsHtml(webview: vscode.Webview, report: Report, files: string[], media: vscode.Uri): string {
  const n = nonce();
  const parts: string[] = [];
  const took = report.total_ms !== undefined ? ` in ${report.total_ms.toFixed(1)} ms` : '';
  const frames = report.frames !== undefined ? ` (${report.frames} frames)` : '';
  parts.push(`<h2>${escapeHtml(report.diagram ?? 'Run')}</h2>`);
  parts.push(`<p class="summary">${report.error ? 'Stopped' : 'Ran'}${escapeHtml(frames + took)}${report.device ? ' on ' + escapeHtml(report.device) : ''}; output in <code>${escapeHtml(report.output ?? '')}</code></p>`);
  if (report.error) {
    const link = report.errorLocation ? ` <a href="#" id="error-location">Go to the place</a>` : '';
    parts.push(`<p class="error">${escapeHtml(report.error)}${link}</p>`);
  }
  if (report.note) parts.push(`<p class="note">${escapeHtml(report.note)}</p>`);
  if (report.figures?.length) {
    const rows = report.figures
      .map((f) => `<tr><td>${escapeHtml(f.stage)}</td><td>${escapeHtml(f.name)}</td><td>${f.value.toFixed(3)}</td></tr>`)
      .join('');
    parts.push(`<h3>Figures</h3><table class="figures"><tr><th>stage</th><th>figure</th><th>value</th></tr>${rows}</table>`);
  }
  if (report.table) parts.push(`<h3>Stages</h3><pre class="table">${escapeHtml(report.table)}</pre>`);
  if (report.calcs?.length) {
    const rows = report.calcs
      .map((c) => `<tr><td>${escapeHtml(c.node)}</td><td>${escapeHtml(c.kernel)}</td><td>${c.launches}</td><td>${c.device_ms.toFixed(2)}</td><td>${c.wall_ms.toFixed(2)}</td></tr>`)
      .join('');
    parts.push(`<h3>Kernels</h3><table><tr><th>node</th><th>kernel</th><th>launches</th><th>GPU ms</th><th>wall ms</th></tr>${rows}</table>`);
  }
  if (report.printed?.length) parts.push(`<h3>Printed</h3><pre>${escapeHtml(report.printed.join(''))}</pre>`);
  const pictures = [...(report.plots ?? []), ...files.filter((f) => f.endsWith('.png') && !(report.plots ?? []).includes(f.replace(/\.png$/, '.svg')))];
  if (pictures.length) {
    const shown = pictures
      .slice(0, INLINE_IMAGES)
      .map((f) => `<figure><img src="${webview.asWebviewUri(vscode.Uri.file(f)).with({ query: `v=${report.revision ?? 0}` })}" alt="${escapeHtml(path.basename(f))}"><figcaption>${escapeHtml(path.basename(f))}</figcaption></figure>`)
      .join('');
    parts.push(`<h3>Pictures</h3><div class="pictures">${shown}</div>`);
  }
  const arrays = files.filter((f) => f.endsWith('.npy')).slice(0, INSPECTED_ARRAYS);
  if (arrays.length) {
    const named = arrays.map((f) => ({
      name: path.relative(report.output ?? '', f) || path.basename(f),
      uri: webview.asWebviewUri(vscode.Uri.file(f)).with({ query: `v=${report.revision ?? 0}` }).toString(),
    }));
    parts.push(`<h3>Arrays</h3><div id="inspector" data-arrays="${escapeHtml(JSON.stringify(named))}">
<label>A <select id="inspect-a"></select></label> <label>show <select id="inspect-mode"><option value="a">A</option><option value="both">A | B</option><option value="difference">A − B</option></select></label>
<label>B <select id="inspect-b"></select></label>
<div id="inspect-scale" class="note"></div><canvas id="inspect-canvas"></canvas><div id="inspect-readout" aria-live="polite"></div></div>`);
  }
  const clouds = files.filter((f) => f.endsWith('.ply')).slice(0, INSPECTED_ARRAYS);
  if (clouds.length) {
    const named = clouds.map((f) => ({
      name: path.relative(report.output ?? '', f) || path.basename(f),
      uri: webview.asWebviewUri(vscode.Uri.file(f)).with({ query: `v=${report.revision ?? 0}` }).toString(),
    }));
    parts.push(`<h3>Point clouds</h3><div id="clouds" data-clouds="${escapeHtml(JSON.stringify(named))}">
<label>cloud <select id="cloud-file"></select></label> <label>colour by <select id="cloud-colour"><option value="depth">depth</option><option value="height">height</option></select></label>
<canvas id="cloud-canvas" width="560" height="400"></canvas><div id="cloud-info" class="note"></div></div>`);
  }
  if (files.length) {
    const list = files.map((f) => `<li><a href="#" data-open="${escapeHtml(f)}">${escapeHtml(path.relative(report.output ?? '', f) || f)}</a></li>`).join('');
    parts.push(`<h3>Files (${files.length})</h3><ul class="files">${list}</ul>`);
  }
  return `<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; img-src ${webview.cspSource}; connect-src ${webview.cspSource}; style-src 'nonce-${n}'; script-src 'nonce-${n}';">
<style nonce="${n}">
body { font-family: var(--vscode-font-family); color: var(--vscode-foreground); padding: 0 12px; }
.error { color: var(--vscode-errorForeground); }
.note { opacity: 0.8; }
pre { font-family: var(--vscode-editor-font-family); background: var(--vscode-textCodeBlock-background); padding: 6px; overflow-x: auto; }
table { border-collapse: collapse; } td, th { padding: 2px 8px; text-align: right; } td:first-child, td:nth-child(2), th { text-align: left; }
.pictures { display: flex; flex-wrap: wrap; gap: 12px; } figure { margin: 0; } img { max-width: 420px; max-height: 320px; background: white; }
figcaption { font-size: 0.9em; opacity: 0.8; }
#inspect-canvas { display: block; margin: 6px 0; max-width: 100%; height: auto; image-rendering: pixelated; cursor: crosshair; }
#inspect-readout { min-height: 1.4em; font-family: var(--vscode-editor-font-family); }
#cloud-canvas { display: block; margin: 6px 0; cursor: grab; touch-action: none; }
</style></head><body>${parts.join('\n')}
<script nonce="${n}">
const vscode = acquireVsCodeApi();
document.addEventListener('click', (e) => {
  const a = e.target.closest('a');
  if (!a) return;
  e.preventDefault();
  if (a.dataset.open) vscode.postMessage({ open: a.dataset.open });
  if (a.id === 'error-location') vscode.postMessage({ location: true });
});
</script>
<script nonce="${n}" src="${webview.asWebviewUri(vscode.Uri.joinPath(media, 'inspect.js'))}"></script>
<script nonce="${n}" src="${webview.asWebviewUri(vscode.Uri.joinPath(media, 'cloud.js'))}"></script></body></html>`;
}
