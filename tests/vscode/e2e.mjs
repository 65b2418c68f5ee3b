// The GU-DSL extension in a real VS Code (code-server) driven by Debian's Chromium as a user
// would: diagnostics appear and clear, completion, the diagram panel (selection both ways, drag
// → layout file, palette → text, undo), a pipeline run with its results, its live preview
// following θ set by a slider and by typing, a run cancelled, the panel on a diagram of every
// kind. A screenshot after each step; exits 1 on the first failure.
// Traffic: 127.0.0.1 only.
//   CS_URL=http://127.0.0.1:8765 WS=workspace RUNS=run-output OUT=screenshots DRIVER=dir node e2e.mjs
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const home = process.env.GUDSL_E2E_HOME || process.cwd();
const { chromium } = createRequire(path.join(process.env.DRIVER || path.join(home, 'driver'), 'package.json'))('playwright-core');
const CS_URL = process.env.CS_URL || 'http://127.0.0.1:8765';
const WS = process.env.WS;
const RUNS = process.env.RUNS;
const OUT = process.env.OUT;
const T = Number(process.env.STEP_TIMEOUT_MS || 60000);
const LISTING = 'listing07_action_transitions.gudsl';
const LISTING_PATH = path.join(WS, 'seed', LISTING);
const LAYOUT_PATH = LISTING_PATH + '.layout';

const t0 = Date.now();
let passed = 0;
const ok = (name, extra = '') => {
  passed++;
  console.log(`ok   ${name} (t=${((Date.now() - t0) / 1000).toFixed(1)}s) ${extra}`);
};

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: [
    '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    // Resolve nothing but 127.0.0.1: no DNS query leaves the machine.
    '--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1',
  ],
});
const context = await browser.newContext({ viewport: { width: 1600, height: 900 } });
const page = await context.newPage();
page.setDefaultTimeout(T);
// Requests for anything but 127.0.0.1. The webviews' own files have https://*.vscode-cdn.net
// addresses that VS Code's service worker answers from the server: those must never reach the
// network (Chromium resolves no other host, so they would fail if they did).
const external = [];
page.on('request', (r) => {
  const u = r.url();
  if (!/^(https?|wss?):\/\/127\.0\.0\.1[:/]/.test(u) && !/^(data|blob|vscode-[a-z-]+):/.test(u)) external.push(r);
});
const leftTheMachine = async () => {
  const left = [];
  for (const r of external) {
    const response = await r.response().catch(() => null);
    const webviewFile = /^https:\/\/[^/]+\.vscode-cdn\.net\//.test(r.url());
    // A webview page replaced while its files load (each live preview rewrites the results page)
    // aborts those loads: they were the service worker's, and never got a response.
    if (webviewFile && !response && r.failure()?.errorText === 'net::ERR_ABORTED') continue;
    if (!(response && response.fromServiceWorker() && webviewFile)) left.push(r.url());
  }
  return left;
};

let shots = 0;
const shot = async (name) => {
  const file = path.join(OUT, `${String(++shots).padStart(2, '0')}-${name}.png`);
  await page.screenshot({ path: file });
  console.log(`     screenshot ${file}`);
};
const quickInput = page.locator('.quick-input-widget input.input');
const palette = async (text) => {
  await page.keyboard.press('F1');
  await quickInput.waitFor({ state: 'visible', timeout: T });
  await quickInput.fill('>' + text);
  await page.locator('.quick-input-list .monaco-list-row', { hasText: text }).first().waitFor({ timeout: T });
  await page.keyboard.press('Enter');
};
const openFile = async (name) => {
  await page.keyboard.press('Control+p');
  await quickInput.waitFor({ state: 'visible', timeout: T });
  await quickInput.fill(name);
  await page.locator('.quick-input-list .monaco-list-row', { hasText: name }).first().waitFor({ timeout: T });
  await page.keyboard.press('Enter');
  await page.locator(`.tab[aria-label*="${name}"]`).first().waitFor({ timeout: T });
};
// The cursor's line as the status bar shows it ("Ln 22, Col 6"): waiting on it keeps keystrokes
// from racing the workbench on a busy machine.
const cursorAt = (line) => page.locator('#status\\.editor\\.selection', { hasText: `Ln ${line},` }).waitFor({ timeout: T });
const goToLine = async (n) => {
  await page.keyboard.press('Control+g');
  await quickInput.waitFor({ state: 'visible', timeout: T });
  await quickInput.fill(':' + n);
  await page.keyboard.press('Enter');
  await page.locator('.quick-input-widget').waitFor({ state: 'hidden', timeout: T });
  await cursorAt(n);
};
const focusEditor = async (name) => {
  await page.locator(`.tab[aria-label*="${name}"]`).first().click();
  await page.locator('.editor-instance .monaco-editor.focused').first().waitFor({ timeout: T });
};
const lineOf = (text, file = LISTING_PATH) => fs.readFileSync(file, 'utf8').split('\n').findIndex((l) => l.includes(text)) + 1;
const until = async (what, test) => {
  const end = Date.now() + T;
  while (Date.now() < end) {
    if (await test()) return;
    await page.waitForTimeout(100);
  }
  throw new Error(`timed out waiting for ${what}`);
};
/** The keyboard in the first editor group's text editor: a webview that reveals itself (the
 * results panel after a run) can take it back just after a file opens, and commands shown only
 * for GU-DSL editors (`editorLangId`) then leave the palette. */
const focusFirstEditor = () =>
  until('the keyboard in the text editor', async () => {
    await page.keyboard.press('Control+1');
    await page.waitForTimeout(200);
    return page.evaluate(() => !!document.activeElement?.closest('.monaco-editor'));
  });
/** The frame of the webview whose page has `selector` (the diagram's `#canvas`, the results' `.summary`). */
const webview = async (selector) => {
  let found;
  await until(`a webview with ${selector}`, async () => {
    for (const frame of page.frames()) {
      if (frame.isDetached()) continue;
      if (await frame.locator(selector).count().catch(() => 0)) {
        found = frame;
        return true;
      }
    }
    return false;
  });
  return found;
};

let failed = false;
try {
  // 1. The workbench on the samples; a sample opens as GU-DSL and the server says it is ready.
  await page.goto(`${CS_URL}/?folder=${encodeURIComponent(WS)}`);
  await page.locator('.monaco-workbench').waitFor({ timeout: T });
  await page.locator('.explorer-folders-view .monaco-list-row').first().waitFor({ timeout: T });
  await openFile(LISTING);
  await page.locator('.statusbar-item', { hasText: 'GU-DSL' }).first().waitFor({ timeout: T });
  await page.locator('.statusbar-item[aria-label*="check"], .statusbar-item:has(.codicon-check)', { hasText: 'GU-DSL' }).first().waitFor({ timeout: T });
  ok('sample opened, language server ready');
  await shot('opened');

  // 2. A diagnostic appears where the text is wrong, and clears when it is undone.
  const guarded = lineOf('=> guardedAction;');
  await focusEditor(LISTING);
  await goToLine(guarded);
  await page.keyboard.press('End');
  await page.keyboard.press('Enter');
  await cursorAt(guarded + 1);
  await page.keyboard.type('=> missingNode;', { delay: 15 });
  await page.locator('.monaco-editor .squiggly-error').first().waitFor({ timeout: T });
  await page.keyboard.press('Control+Shift+m');
  await page.locator('.markers-panel .monaco-list-row', { hasText: 'missingNode' }).first().waitFor({ timeout: T });
  ok('diagnostic appears (squiggle, Problems)');
  await shot('diagnostic');
  await focusEditor(LISTING);
  for (let i = 0; i < 3; i++) await page.keyboard.press('Control+z');
  await until('the squiggle to clear', async () => (await page.locator('.monaco-editor .squiggly-error').count()) === 0);
  ok('diagnostic clears after undo');

  // 3. Completion after `=> ` lists the diagram's nodes.
  await goToLine(guarded);
  await page.keyboard.press('End');
  await page.keyboard.press('Enter');
  await page.keyboard.type('=> ', { delay: 15 });
  await page.keyboard.press('Control+Space');
  const suggest = page.locator('.editor-widget.suggest-widget.visible');
  await suggest.locator('.monaco-list-row', { hasText: 'nonguardedAction' }).first().waitFor({ timeout: T });
  ok('completion after "=> "', JSON.stringify(await suggest.locator('.monaco-list-row .label-name').allInnerTexts()));
  await shot('completion');
  await page.keyboard.press('Escape');
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+z');

  // 4. The diagram panel shows the diagram under the cursor; cursor → node, click → cursor.
  await goToLine(lineOf('action guardedAction'));
  await palette('GU-DSL: Show Diagram');
  const diagram = await webview('#canvas svg');
  const canvas = diagram.locator('#canvas');
  await until('the panel to highlight guardedAction', async () => (await canvas.getAttribute('data-selected')) === 'TransitionExample/Lane/guardedAction');
  ok('diagram panel: cursor in a declaration highlights its node');
  await shot('diagram-panel');
  const nonguarded = diagram.locator('g.node[data-id="TransitionExample/Lane/nonguardedAction"]');
  await nonguarded.click();
  // The click leaves the keyboard in the panel (Del, F2 act there); the editor shows the cursor.
  await page.keyboard.press('Control+1');
  await cursorAt(lineOf('action nonguardedAction'));
  ok('diagram panel: clicking a node puts the cursor on its declaration');

  // 5. Dragging a node pins it: the server writes the layout sidecar, the panel redraws.
  const box = await nonguarded.boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(box.x + box.width / 2 - 6 * i, box.y + box.height / 2 + 4 * i);
  await page.mouse.up();
  await until('the layout file', async () => fs.existsSync(LAYOUT_PATH) && fs.readFileSync(LAYOUT_PATH, 'utf8').includes('nonguardedAction'));
  await diagram.locator('g.node.pinned[data-id="TransitionExample/Lane/nonguardedAction"]').waitFor({ timeout: T });
  ok('drag → layout file written, node drawn pinned', fs.readFileSync(LAYOUT_PATH, 'utf8').replace(/\s+/g, ' ').slice(0, 160));
  await shot('dragged');

  // 6. The palette creates a node: the text changes (an edit the editor can undo).
  await diagram.locator('button[data-action="create-action"]').click();
  await quickInput.waitFor({ state: 'visible', timeout: T });
  await quickInput.fill('paletteAction');
  await page.keyboard.press('Enter');
  await diagram.locator('g.node[data-id="TransitionExample/Lane/paletteAction"]').waitFor({ timeout: T });
  await focusEditor(LISTING);
  await page.keyboard.press('Control+s');
  await until('the saved text to have the new node', async () => fs.readFileSync(LISTING_PATH, 'utf8').includes('paletteAction'));
  ok('palette → new node in the text and the diagram');
  await shot('palette-create');
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+s');
  await until('undo to remove it', async () => !fs.readFileSync(LISTING_PATH, 'utf8').includes('paletteAction'));
  await until('the diagram to drop it', async () => (await diagram.locator('g.node[data-id="TransitionExample/Lane/paletteAction"]').count()) === 0);
  ok('undo in the editor takes the node back out of text and diagram');

  // 7. Connect from the palette, delete from the context menu: the text follows both.
  const transitions = () => (fs.readFileSync(LISTING_PATH, 'utf8').match(/=> nonguardedAction;/g) || []).length;
  const before = transitions();
  const edgeId = 'TransitionExample/Lane/guardedAction->TransitionExample/Lane/nonguardedAction#0';
  await diagram.locator('button[data-action="connect"]').click();
  await diagram.locator('g.node[data-id="TransitionExample/Lane/guardedAction"]').click();
  await diagram.locator('g.node[data-id="TransitionExample/Lane/nonguardedAction"]').click();
  const edge = diagram.locator(`polyline.edge-hit[data-id="${edgeId}"]`);
  await edge.waitFor({ state: 'attached', timeout: T });
  await focusEditor(LISTING);
  await page.keyboard.press('Control+s');
  await until('the new transition in the text', async () => transitions() === before + 1);
  ok('palette connect → a transition in the text and the diagram');
  await shot('connected');
  // Right-click on the middle of the new edge's route.
  const spot = await edge.evaluate((line) => {
    const point = line.getPointAtLength(line.getTotalLength() / 2).matrixTransform(line.getScreenCTM());
    const box = line.getBoundingClientRect();
    return { x: point.x - box.x, y: point.y - box.y };
  });
  await edge.click({ button: 'right', position: spot, force: true });
  await diagram.locator('#menu .item', { hasText: 'Delete' }).click();
  await until('the edge to leave the diagram', async () => (await diagram.locator(`polyline.edge[data-id="${edgeId}"]`).count()) === 0);
  await focusEditor(LISTING);
  await page.keyboard.press('Control+s');
  await until('the transition to leave the text', async () => transitions() === before);
  ok('context menu delete → the transition out of text and diagram');

  // 8. ▶ Run pipeline: progress, then the results panel with the stages' table and plot.
  await openFile('ch4_motion_compensation.gudsl');
  await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Run pipeline' }).first().click();
  const results = await webview('.summary');
  await results.locator('pre.table', { hasText: 'ToF.MotionCompensation' }).waitFor({ timeout: T });
  await results.locator('.pictures img').first().waitFor({ timeout: T });
  const summary = await results.locator('.summary').innerText();
  if (!fs.existsSync(path.join(RUNS, 'MotionCompensationPipeline', 'report.json'))) throw new Error('no report.json in the output folder');
  ok('pipeline ran, results panel shows table and plot', summary.slice(0, 120));
  await shot('pipeline-results');
  // The arrays it wrote, inspected: a colour map with its scale, the value under the cursor in
  // cm, and the difference of two.
  const inspector = results.locator('#inspector');
  await inspector.scrollIntoViewIfNeeded();
  await until('the distance drawn', async () => /distance_0000\.npy: [\d.]+ cm … [\d.]+ cm/.test(await results.locator('#inspect-scale').innerText()));
  const picture = results.locator('#inspect-canvas');
  await picture.hover({ position: { x: 100, y: 100 } });
  await until('the value under the cursor', async () => /^\(\d+, \d+\): [\d.]+ cm$/.test(await results.locator('#inspect-readout').innerText()));
  const under = await results.locator('#inspect-readout').innerText();
  await results.locator('#inspect-mode').selectOption('difference');
  await until('A − B drawn', async () => (await results.locator('#inspect-scale').innerText()).startsWith('A − B'));
  ok('arrays inspected: colour map, value under the cursor, A − B', under);
  await shot('pipeline-inspected');

  // 8b. Live preview: on from its lens, θ changed by the diagram's slider and by typing, and
  // the preview's error figure follows each; the diagram shows the stages' times.
  const CH4 = path.join(WS, 'pipelines', 'ch4_motion_compensation.gudsl');
  // Each preview rewrites the results page: its frame is looked up again each time.
  const compensated = async () => {
    const shown = await webview('table.figures');
    const row = shown.locator('table.figures tr:has(td:text-is("Compensated mean_cm"))');
    return (await row.count()) ? (await row.locator('td').nth(2).innerText()).trim() : null;
  };
  const figureChange = async (from, how) => {
    let now;
    await until(`the compensated error to change (${how})`, async () => (now = await compensated().catch(() => null)) !== null && now !== from);
    return now;
  };
  await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Live preview' }).first().click();
  await until('the live preview in the results panel', async () =>
    (await webview('.summary')).locator('h2', { hasText: '(live)' }).count().catch(() => 0));
  let live0;
  await until('the first preview\'s figures', async () => (live0 = await compensated().catch(() => null)) !== null);
  ok('live preview on: the first frame previewed', `compensated ${live0} cm`);
  await shot('preview');
  await focusFirstEditor();
  await goToLine(lineOf('Motion instantiates', CH4));
  await palette('GU-DSL: Show Diagram');
  const timed = await webview('#params');
  const theta = timed.locator('#params input[data-name="threshold"]');
  await theta.waitFor({ timeout: T });
  await timed.locator('#canvas text', { hasText: 'ms/frame' }).first().waitFor({ timeout: T });
  ok('the diagram shows the stages\' times, the parameters of the instance under the cursor');
  await shot('timed-diagram');
  // The slider as a keyboard moves it: End takes it to its maximum, 100 %.
  await timed.locator('#params input[data-name="threshold.slider"]').focus();
  await page.keyboard.press('End');
  const live1 = await figureChange(live0, 'slider');
  await until('θ = 100 in the text', async () => page.locator('.view-line', { hasText: 'threshold = 100' }).count().then((n) => n > 0));
  ok('θ by the slider: written into the text, the preview follows', `compensated ${live0} → ${live1} cm`);
  await shot('preview-slider');
  await focusFirstEditor();
  await page.keyboard.press('Control+f');
  await page.keyboard.type('threshold = 100', { delay: 10 });
  await page.locator('.find-widget.visible').waitFor({ timeout: T });
  await page.keyboard.press('Enter');
  await page.locator('#status\\.editor\\.selection', { hasText: '(15 selected)' }).waitFor({ timeout: T });
  // (Escape here can reach the workbench instead of the find widget: its close button is sure.)
  await page.locator('.find-widget.visible [aria-label^="Close"]').first().click();
  await page.locator('.find-widget.visible').waitFor({ state: 'hidden', timeout: T });
  await page.locator('#status\\.editor\\.selection', { hasText: '(15 selected)' }).waitFor({ timeout: T });
  await page.keyboard.type('threshold = 3', { delay: 30 });
  const live2 = await figureChange(live1, 'typing');
  ok('θ by typing: the preview follows', `compensated ${live1} → ${live2} cm`);
  await shot('preview-typed');
  // Off again: the lens is above the diagram's first line. (Lenses are drawn again after each
  // edit: a click on one being replaced does nothing, so it is clicked until the status says off.)
  await page.keyboard.press('Control+Home');
  await until('the live preview off', async () => {
    await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Live preview' }).first().click();
    return page.locator('.statusbar-item', { hasText: 'live preview off' }).first().waitFor({ timeout: 3000 }).then(() => true, () => false);
  });
  await palette('Notifications: Clear All Notifications');

  // 8c. Motion compensation looked into: its mask as a picture, its flow field as a colour
  // wheel with arrows (the vector under the cursor), compensated − uncompensated.
  await focusFirstEditor();
  await openFile('ch4_motion_taps.gudsl');
  await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Run pipeline' }).first().click();
  let taps;
  await until('the taps\' results', async () => {
    taps = await webview('#inspector');
    return (await taps.locator('h2').innerText().catch(() => '')).startsWith('MotionTapsPipeline');
  });
  await taps.locator('.pictures img[alt="mask_0000.png"]').waitFor({ timeout: T });
  await taps.locator('#inspect-a').selectOption({ label: 'Flows/flow_0000.npy' });
  await until('the flow drawn', async () => (await taps.locator('#inspect-scale').innerText()).startsWith('flow:'));
  await taps.locator('#inspector').scrollIntoViewIfNeeded();
  await taps.locator('#inspect-canvas').hover({ position: { x: 200, y: 200 } });
  await until('the flow under the cursor', async () => /px per phase image/.test(await taps.locator('#inspect-readout').innerText()));
  ok('the flow field: colour wheel, arrows, the vector under the cursor', await taps.locator('#inspect-readout').innerText());
  await shot('flow-field');
  await taps.locator('#inspect-a').selectOption({ label: 'CompensatedDepth/distance_0000.npy' });
  await taps.locator('#inspect-b').selectOption({ label: 'UncompensatedDepth/distance_0000.npy' });
  await taps.locator('#inspect-mode').selectOption('difference');
  await until('compensated − uncompensated drawn', async () => /^A − B: -?[\d.]+ cm/.test(await taps.locator('#inspect-scale').innerText()));
  ok('compensated − uncompensated', (await taps.locator('#inspect-scale').innerText()).split('(')[0]);
  await shot('difference');
  await taps.locator('#inspect-mode').selectOption('both');
  await until('A | B drawn side by side', async () => (await taps.locator('#inspect-scale').innerText()).startsWith('A | B'));
  const pairBox = await taps.locator('#inspect-canvas').boundingBox();
  await taps.locator('#inspect-canvas').hover({ position: { x: pairBox.width * 0.75, y: pairBox.height / 2 } });
  await until('B\'s value under the cursor', async () => /^B \(\d+, \d+\): /.test(await taps.locator('#inspect-readout').innerText()));
  ok('side by side on one scale', await taps.locator('#inspect-readout').innerText());
  await shot('side-by-side');
  await focusFirstEditor();

  // 9. A long run is cancelled from its notification.
  await openFile('long_pipeline.gudsl');
  await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Run pipeline' }).first().click();
  const toast = page.locator('.notification-toast', { hasText: 'Running LongMotionPipeline' });
  await toast.locator('text=/frame \\d+ of 400/').first().waitFor({ timeout: T });
  await shot('pipeline-progress');
  await toast.hover();
  await toast.locator('.monaco-button', { hasText: 'Cancel' }).first().click();
  await page.locator('.notification-toast', { hasText: 'run cancelled' }).first().waitFor({ timeout: T });
  ok('long run cancelled from the notification');
  await shot('pipeline-cancelled');

  // 9b. Chapter 6's scan: its point cloud in 3D in the results panel, orbited by a drag.
  await focusFirstEditor();
  await openFile('ch6_object_scan.gudsl');
  await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Run pipeline' }).first().click();
  let scanned;
  await until('the scan\'s point cloud drawn', async () => {
    scanned = await webview('#cloud-info');
    return /^\d+ points, [\d.]+ m across/.test(await scanned.locator('#cloud-info').innerText().catch(() => ''));
  });
  const cloudCanvas = scanned.locator('#cloud-canvas');
  await cloudCanvas.scrollIntoViewIfNeeded();
  const cloudBox = await cloudCanvas.boundingBox();
  await page.mouse.move(cloudBox.x + cloudBox.width / 2, cloudBox.y + cloudBox.height / 2);
  await page.mouse.down();
  for (let i = 1; i <= 8; i++) await page.mouse.move(cloudBox.x + cloudBox.width / 2 + 12 * i, cloudBox.y + cloudBox.height / 2 + 3 * i);
  await page.mouse.up();
  ok('chapter 6: the point cloud in 3D, orbited', (await scanned.locator('#cloud-info').innerText()).split(';')[0]);
  await shot('point-cloud');
  await focusFirstEditor(); // the drag left the keyboard in the results panel

  // 10. The panel follows the editor to a diagram of each other kind (one screenshot each, with
  // the side bar, the bottom panel and the notifications out of the way).
  await page.keyboard.press('Control+b');
  await palette('View: Hide Panel');
  await palette('Notifications: Clear All Notifications');
  for (const [file, name] of [
    ['appendixA_associations.gudsl', 'Associations'],
    ['listing27_component_example.gudsl', 'ComponentExampleDiagram'],
    ['listing28_component_instance_example.gudsl', 'ComponentInstanceExampleDiagram'],
  ]) {
    await page.keyboard.press('Control+1');
    await openFile(file);
    await focusFirstEditor();
    await palette('GU-DSL: Show Diagram');
    const panel = await webview('#canvas svg');
    await until(`the panel to show ${name}`, async () => (await panel.locator('#canvas').getAttribute('data-diagram')) === name);
    // A synthetic click: a real one would leave the keyboard in the panel, away from Ctrl+P.
    await panel.locator('button[data-action="zoom-fit"]').dispatchEvent('click');
    await page.waitForTimeout(300);
    await shot(`panel-${name}`);
  }
  ok('the panel follows the editor: class, component and component-instance diagrams drawn');
} catch (e) {
  failed = true;
  console.log(`FAIL ${String(e).split('\n')[0]}`);
  await shot('failure').catch(() => {});
}
const left = await leftTheMachine();
if (left.length) {
  failed = true;
  console.log(`FAIL requests left 127.0.0.1: ${JSON.stringify(left.slice(0, 10))}`);
} else {
  ok('no request left 127.0.0.1', `(${external.length} webview files from the service worker)`);
}
await browser.close();
console.log(`${passed} passed${failed ? ', 1 failed' : ''} in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
process.exit(failed ? 1 : 0);
