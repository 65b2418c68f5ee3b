// The diagram panel's page (vscode-extension/media/diagram.js and diagram.css, as the extension
// serves them) on a large diagram in headless Chromium: how long the page takes to show the
// server's SVG, and how long each frame takes while the user zooms (the palette's buttons,
// Ctrl+wheel), once zooming pauses, and while the user pans (scrolling). A frame is timed from
// the action to the second animation frame after it: 33 ms at 60 Hz is as fast as it shows. Chromium runs without a GPU (software raster, as here and in
// CI): a machine with one draws faster.
//   node bench_panel.mjs DIAGRAM.svg [DRIVER_DIR]
// DRIVER_DIR holds playwright-core (tests/vscode/setup.sh installs it). Prints a JSON line.
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const [svgPath, driver = path.join(process.env.GUDSL_E2E_HOME || '', 'driver')] = process.argv.slice(2);
const { chromium } = createRequire(path.join(driver, 'package.json'))('playwright-core');
const media = path.join(path.dirname(fileURLToPath(import.meta.url)), '..', '..', 'vscode-extension', 'media');
const svg = fs.readFileSync(svgPath, 'utf8');

const page_html = `<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">
<style>${fs.readFileSync(path.join(media, 'diagram.css'), 'utf8')}</style></head>
<body><div id="toolbar"></div><div id="status"></div><div id="canvas" tabindex="0"></div>
<div id="params" hidden></div><div id="menu" hidden></div>
<script>window.acquireVsCodeApi = () => ({ postMessage() {}, getState() {}, setState() {} });</script>
<script>${fs.readFileSync(path.join(media, 'diagram.js'), 'utf8')}</script></body></html>`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--no-first-run', '--host-resolver-rules=MAP * ~NOTFOUND'],
});
const page = await (await browser.newContext({ viewport: { width: 1600, height: 900 } })).newPage();
await page.setContent(page_html);

// Each measure resolves after the frame that shows its effect has been painted.
const result = await page.evaluate(async (svg) => {
  const frame = () => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
  const timed = async (action) => {
    const start = performance.now();
    action();
    await frame();
    return performance.now() - start;
  };
  const canvas = document.getElementById('canvas');
  const show = await timed(() => window.postMessage({ type: 'graph', kind: 'class', name: 'Bench', version: 1, svg, nodes: [] }, '*'));
  // The message is handled in a task of its own: wait until the SVG is there.
  while (!canvas.querySelector('svg')) await frame();
  await frame();
  const elements = canvas.querySelectorAll('*').length;
  const click = (title) => document.querySelector(`button[title="${title}"]`).click();
  const fitMs = await timed(() => click('Zoom to fit'));
  const zoomIn = [];
  for (let i = 0; i < 6; i++) zoomIn.push(await timed(() => click('Zoom in')));
  const wheel = [];
  for (let i = 0; i < 6; i++) {
    wheel.push(await timed(() => canvas.dispatchEvent(new WheelEvent('wheel', { deltaY: 100, ctrlKey: true, bubbles: true, cancelable: true }))));
  }
  // Zooming paused: the panel may draw the diagram anew at its new size (one longer frame).
  const settle = [];
  const pause = performance.now();
  while (performance.now() - pause < 500) settle.push(await timed(() => {}));
  const pan = [];
  for (let i = 0; i < 20; i++) pan.push(await timed(() => { canvas.scrollTop += 150; canvas.scrollLeft += 100; }));
  const stats = (v) => {
    const s = [...v].sort((a, b) => a - b);
    return { median: +s[Math.floor(s.length / 2)].toFixed(1), max: +s[s.length - 1].toFixed(1) };
  };
  return { elements, showMs: +show.toFixed(1), fitMs: +fitMs.toFixed(1), zoomInMs: stats(zoomIn), wheelMs: stats(wheel), settleMs: stats(settle), panMs: stats(pan) };
}, svg);
console.log(JSON.stringify({ svg: path.basename(svgPath), bytes: svg.length, ...result }));
await browser.close();
