// The diagram panel's page: draws the server's SVG, and turns clicks, drags, the palette, the
// context menu and keys into messages for the extension (which sends them to the server as
// `gudsl/applyGraphEdit` operations). It never edits the model itself: the next graph shows
// what the server made of each gesture.
(function () {
  'use strict';
  const vscode = acquireVsCodeApi();
  const canvas = document.getElementById('canvas');
  const toolbar = document.getElementById('toolbar');
  const status = document.getElementById('status');
  const menu = document.getElementById('menu');
  const params = document.getElementById('params');

  /** What each diagram kind's palette creates: [operation kind, button label]. */
  const PALETTE = {
    class: [['class', 'Class'], ['interface', 'Interface'], ['enum', 'Enum']],
    activity: [['action', 'Action'], ['decision', 'Decision'], ['fork', 'Fork'], ['join', 'Join'], ['calc', 'Calc'], ['loop', 'Loop'], ['start', 'Start'], ['final', 'Final']],
    component: [['component', 'Component']],
    componentInstance: [['instance', 'Instance']],
  };
  /** The shapes of the activity nodes that can hold nodes. */
  const CONTAINERS = ['action', 'decision', 'loop', 'loopWindow'];
  /** Movement (screen pixels) below which a press is a click, not a drag. */
  const DRAG_THRESHOLD = 3;

  let graph = null; // the last graph: {kind, name, version, svg, nodes, groups}
  let nodes = new Map(); // id -> node of the graph
  let selected = null; // id of the selected element
  let connectFrom = null; // id of a connection's source while connecting
  let connecting = false;
  let zoom = 1;
  let drag = null;

  let heldGraph = null; // a graph that came during a drag, shown when it ends
  window.addEventListener('message', (event) => {
    const m = event.data;
    if (m.type === 'graph' && drag) heldGraph = m;
    else if (m.type === 'graph') show(m);
    else if (m.type === 'highlight') select(m.id, false);
    else if (m.type === 'message') say(m.text, true);
    else if (m.type === 'parameters') showParameters(m);
  });

  function show(m) {
    const kindChanged = !graph || graph.kind !== m.kind;
    graph = m;
    nodes = new Map(m.nodes.map((n) => [n.id, n]));
    canvas.innerHTML = m.svg || '';
    const svg = canvas.querySelector('svg');
    if (svg) {
      svg.dataset.width = svg.getAttribute('width');
      svg.dataset.height = svg.getAttribute('height');
      // A wide invisible twin of each edge makes thin lines easy to hit.
      for (const edge of svg.querySelectorAll('polyline.edge')) {
        const hit = edge.cloneNode(false);
        hit.setAttribute('class', 'edge-hit');
        hit.removeAttribute('marker-end');
        hit.removeAttribute('marker-start');
        edge.after(hit);
      }
      for (const n of m.nodes) {
        if (n.pinned) element(n.id)?.classList.add('pinned');
      }
      drawZoomed();
    }
    if (kindChanged) palette();
    canvas.dataset.version = String(m.version);
    canvas.dataset.diagram = m.name;
    if (selected && !element(selected)) selected = null;
    markSelected();
    say(m.layoutError ? `Layout file not used: ${m.layoutError}` : '', !!m.layoutError);
  }

  /** How long a slider rests before its value is written (each write is an edit and a preview). */
  const SLIDE_PAUSE_MS = 120;

  /** An instance's parameters as controls: a slider and a number for a value with a range, a
   * number, a checkbox, a list of an enum's members, or text; each change is sent to be written
   * into the model's text. `m.parameters` null: none shown. */
  function showParameters(m) {
    params.hidden = !m.parameters;
    if (!m.parameters) return;
    const names = m.parameters.map((p) => p.name).join(' ');
    if (params.dataset.instance === m.instance && params.dataset.names === names) {
      // The same controls: new values, but the one in the user's hand (a slider held) keeps its own.
      for (const p of m.parameters) {
        for (const el of params.querySelectorAll(`[data-name="${CSS.escape(p.name)}"], [data-name="${CSS.escape(p.name)}.slider"]`)) {
          if (el === document.activeElement) continue;
          if (el.type === 'checkbox') el.checked = p.value === 'true';
          else el.value = p.value ?? '';
        }
      }
      return;
    }
    params.dataset.instance = m.instance;
    params.dataset.names = names;
    const focused = document.activeElement && params.contains(document.activeElement) ? document.activeElement.dataset.name : null;
    params.textContent = '';
    const title = document.createElement('h3');
    title.textContent = `${m.instance} : ${m.component.split('.').pop()}`;
    params.append(title);
    for (const p of m.parameters) params.append(control(m.instance, p));
    if (focused) params.querySelector(`[data-name="${CSS.escape(focused)}"]`)?.focus();
  }

  function control(instance, p) {
    const row = document.createElement('label');
    row.className = 'param';
    row.title = `${p.name} : ${p.type}${p.min !== null ? ` (${p.min} to ${p.max})` : ''}${p.written ? '' : ' — the default'}`;
    const name = document.createElement('span');
    name.textContent = p.name;
    row.append(name);
    const set = (value) => post({ type: 'setParameter', instance, parameter: p.name, value: String(value) });
    const number = ['int', 'float', 'double', 'unsigned', 'uint', 'long', 'short'].includes(p.type);
    if (p.choices.length) {
      const select = input('select', p);
      for (const choice of p.choices) select.append(new Option(choice.split('.').pop(), choice, false, choice === p.value));
      select.addEventListener('change', () => set(select.value));
      row.append(select);
    } else if (p.type === 'bool') {
      const box = input('input', p);
      box.type = 'checkbox';
      box.checked = p.value === 'true';
      box.addEventListener('change', () => set(box.checked));
      row.append(box);
    } else if (number) {
      const field = input('input', p);
      field.type = 'number';
      field.value = p.value ?? '';
      const step = p.step ?? 'any';
      field.step = String(step);
      field.addEventListener('change', () => field.value !== '' && set(field.value));
      if (p.min !== null && p.max !== null) {
        const slider = input('input', p, 'slider');
        slider.type = 'range';
        [slider.min, slider.max, slider.step] = [p.min, p.max, p.step ?? (p.max - p.min) / 200];
        slider.value = p.value ?? p.min;
        let pause;
        slider.addEventListener('input', () => {
          field.value = slider.value;
          clearTimeout(pause);
          pause = setTimeout(() => set(slider.value), SLIDE_PAUSE_MS);
        });
        row.append(slider);
      }
      row.append(field);
    } else {
      // Text as typed, without the model's quotes (the server writes them).
      const field = input('input', p);
      field.value = p.value?.startsWith('"') ? JSON.parse(p.value) : p.value ?? '';
      field.addEventListener('change', () => set(field.value));
      row.append(field);
    }
    return row;
  }

  function input(tag, p, role) {
    const el = document.createElement(tag);
    el.dataset.name = role ? `${p.name}.${role}` : p.name;
    el.setAttribute('aria-label', role ? `${p.name} slider` : p.name);
    return el;
  }

  function element(id) {
    return id ? canvas.querySelector(`[data-id="${CSS.escape(id)}"]:not(.edge-hit)`) : null;
  }

  function palette() {
    toolbar.textContent = '';
    for (const [kind, label] of PALETTE[graph.kind] || []) {
      button(`+ ${label}`, `Create a ${label.toLowerCase()}`, () => create(kind), `create-${kind}`);
    }
    separator();
    button('Connect', 'Connect two elements: click the source, then the target', () => startConnect(null), 'connect');
    button('Rename', 'Rename the selected element (F2)', () => selected && post({ type: 'rename', id: selected }), 'rename');
    button('Delete', 'Delete the selected element (Del)', () => selected && post({ type: 'delete', id: selected }), 'delete');
    separator();
    button('Re-layout', 'Lay the nodes no pin holds out afresh', () => post({ type: 'relayout', page: page() }), 'relayout');
    button('−', 'Zoom out', () => setZoom(zoom / 1.25), 'zoom-out');
    button('Fit', 'Zoom to fit', fit, 'zoom-fit');
    button('+', 'Zoom in', () => setZoom(zoom * 1.25), 'zoom-in');
  }

  function button(text, title, action, name) {
    const b = document.createElement('button');
    b.textContent = text;
    b.title = title;
    b.dataset.action = name;
    b.addEventListener('click', action);
    toolbar.append(b);
  }

  function separator() {
    const s = document.createElement('span');
    s.className = 'separator';
    toolbar.append(s);
  }

  /** A new node; in a diagram with swimlanes, into the selected lane or the selected node's. */
  function create(kind) {
    let parent;
    if (graph.kind === 'activity' && selected) {
      parent = graph.groups.includes(selected) ? selected : nodes.get(selected)?.group ?? undefined;
    }
    post({ type: 'create', kind, parent });
  }

  function startConnect(source) {
    connecting = true;
    connectFrom = source;
    document.body.classList.add('connecting');
    say(source ? `Connect ${source} to… (click the target, Esc cancels)` : 'Connect: click the source, then the target (Esc cancels)');
  }

  function stopConnect() {
    connecting = false;
    connectFrom = null;
    document.body.classList.remove('connecting');
    say('');
  }

  function say(text, warning) {
    status.textContent = text || '';
    status.classList.toggle('warning', !!warning);
  }

  function post(message) {
    vscode.postMessage(message);
  }

  function select(id, fromView) {
    selected = id && element(id) ? id : null;
    markSelected();
    if (selected && !fromView) {
      const el = element(selected);
      const box = el.getBoundingClientRect();
      if (box.bottom < 0 || box.top > window.innerHeight || box.right < 0 || box.left > window.innerWidth) {
        el.scrollIntoView({ block: 'center', inline: 'center' });
      }
    }
    if (selected && fromView) post({ type: 'select', id: selected });
  }

  function markSelected() {
    for (const el of canvas.querySelectorAll('.selected')) el.classList.remove('selected');
    element(selected)?.classList.add('selected');
    canvas.dataset.selected = selected || '';
  }

  /** The model element an event's target belongs to: a port, an edge, a node or a lane. */
  function targetOf(event) {
    const el = event.target.closest('[data-id]');
    return el ? el.dataset.id : null;
  }

  function setZoom(z) {
    zoom = Math.min(4, Math.max(0.1, z));
    applyZoom();
  }

  /** How long zooming must pause before the diagram is drawn anew at the new size. */
  const ZOOM_SETTLE_MS = 150;
  let drawnZoom = 1; // the zoom the SVG is drawn at (its width and height)
  let zoomTimer = null;

  /** A zoom shows at once as a scale of what is drawn — cheap, where drawing thousands of
   * elements anew takes a large diagram a tenth of a second or more (tests/vscode/bench_panel.mjs)
   * — and the SVG is drawn at its new size once zooming pauses. */
  function applyZoom() {
    const svg = canvas.querySelector('svg');
    if (!svg) return;
    const scale = zoom / drawnZoom;
    svg.style.transformOrigin = '0 0';
    svg.style.transform = scale === 1 ? '' : `scale(${scale})`;
    clearTimeout(zoomTimer);
    zoomTimer = setTimeout(drawZoomed, ZOOM_SETTLE_MS);
  }

  /** The SVG drawn at the zoom (its size set, no scale left). */
  function drawZoomed() {
    clearTimeout(zoomTimer);
    const svg = canvas.querySelector('svg');
    if (!svg) return;
    svg.setAttribute('width', String(Number(svg.dataset.width) * zoom));
    svg.setAttribute('height', String(Number(svg.dataset.height) * zoom));
    svg.style.transform = '';
    drawnZoom = zoom;
  }

  /** The smallest text Fit draws, in screen pixels: a diagram that would need smaller text to
   * fit is drawn at this size and the panel scrolls (− still zooms out further). */
  const READABLE_PX = 9;

  function fit() {
    const svg = canvas.querySelector('svg');
    if (!svg) return;
    const w = Number(svg.dataset.width);
    const h = Number(svg.dataset.height);
    const fits = Math.min((canvas.clientWidth - 8) / w, (canvas.clientHeight - 8) / h, 2);
    const sizes = [...svg.querySelectorAll('[font-size]')].map((e) => Number(e.getAttribute('font-size'))).filter((n) => n > 0);
    const readable = sizes.length ? READABLE_PX / Math.min(...sizes) : 0;
    setZoom(Math.max(fits, readable));
    canvas.dataset.fit = fits < readable ? 'readable' : 'whole';
    if (fits < readable) say('Fit keeps the text readable: scroll to see the rest (− zooms out further)');
  }

  // Dragging a node moves it (and the nodes drawn inside it) until the server's new graph comes.
  canvas.addEventListener('pointerdown', (event) => {
    hideMenu();
    if (event.button !== 0) return;
    const id = targetOf(event);
    if (connecting) {
      if (!id) return;
      if (!connectFrom) startConnect(id);
      else {
        post({ type: 'connect', source: connectFrom, target: id });
        stopConnect();
      }
      event.preventDefault();
      return;
    }
    const nodeEl = event.target.closest('g.node');
    const node = nodeEl && nodes.get(nodeEl.dataset.id);
    if (node && node.bounds && !event.target.closest('.port')) {
      const svg = canvas.querySelector('svg');
      const moved = [nodeEl, ...[...nodes.values()].filter((n) => inside(n, node.id)).map((n) => element(n.id)).filter(Boolean)];
      drag = { id: node.id, node, els: moved, x: event.clientX, y: event.clientY, scale: svg.getScreenCTM().a, dx: 0, dy: 0, moving: false, pointer: event.pointerId };
      canvas.setPointerCapture(event.pointerId);
      event.preventDefault();
    } else {
      select(id, true);
    }
  });

  /** Whether `n` is drawn inside the node `ancestor` (nested components). */
  function inside(n, ancestor) {
    for (let p = n.parent; p; p = nodes.get(p)?.parent) if (p === ancestor) return true;
    return false;
  }

  canvas.addEventListener('pointermove', (event) => {
    if (!drag || event.pointerId !== drag.pointer) return;
    if ((event.buttons & 1) === 0) return cancelDrag();
    const sx = event.clientX - drag.x;
    const sy = event.clientY - drag.y;
    if (!drag.moving && Math.hypot(sx, sy) < DRAG_THRESHOLD) return;
    drag.moving = true;
    drag.dx = sx / drag.scale;
    drag.dy = sy / drag.scale;
    for (const el of drag.els) el.setAttribute('transform', `translate(${drag.dx} ${drag.dy})`);
    document.body.classList.add('dragging');
  });

  /** A drag the pointer left without a release (capture lost, Esc): the node goes back. */
  function cancelDrag() {
    if (!drag) return;
    for (const el of drag.els) el.removeAttribute('transform');
    endDrag();
  }

  function endDrag() {
    drag = null;
    document.body.classList.remove('dragging');
    if (heldGraph) {
      const m = heldGraph;
      heldGraph = null;
      show(m);
    }
  }

  canvas.addEventListener('pointercancel', cancelDrag);
  canvas.addEventListener('lostpointercapture', () => setTimeout(cancelDrag, 0));

  canvas.addEventListener('pointerup', (event) => {
    if (!drag || event.pointerId !== drag.pointer) return;
    const d = drag;
    endDrag();
    if (d.moving) {
      const x = Math.max(0, Math.round(d.node.bounds.x + d.dx));
      const y = Math.max(0, Math.round(d.node.bounds.y + d.dy));
      say(`Moved ${d.id} to ${x}, ${y}`);
      post({ type: 'move', id: d.id, x, y });
    } else {
      select(d.id, true);
    }
  });

  canvas.addEventListener('dblclick', (event) => {
    const id = targetOf(event);
    if (id && nodes.has(id)) post({ type: 'rename', id });
  });

  canvas.addEventListener('wheel', (event) => {
    if (!event.ctrlKey) return;
    event.preventDefault();
    setZoom(zoom * (event.deltaY < 0 ? 1.1 : 1 / 1.1));
  }, { passive: false });

  canvas.addEventListener('contextmenu', (event) => {
    event.preventDefault();
    const id = targetOf(event);
    if (id) select(id, true);
    const items = [];
    if (id && (nodes.has(id) || element(id)?.matches('.edge, .port, .node'))) {
      items.push(['Go to declaration', () => post({ type: 'select', id, focus: true })]);
      if (nodes.has(id)) items.push(['Rename…', () => post({ type: 'rename', id })]);
      items.push(['Connect from here…', () => startConnect(id)]);
      if (nodes.get(id)?.pinned) items.push(['Unpin (back to the automatic layout)', () => post({ type: 'unpin', id })]);
      items.push(['Delete', () => post({ type: 'delete', id })]);
    }
    if (id && graph.groups.includes(id)) {
      for (const [kind, label] of PALETTE.activity) items.push([`New ${label.toLowerCase()} in this lane…`, () => post({ type: 'create', kind, parent: id })]);
    }
    // Action, decision, loop and loopWindow nodes hold a flow of their own (Sec. 9.2.2.3).
    if (id && CONTAINERS.includes(nodes.get(id)?.shape)) {
      for (const [kind, label] of PALETTE.activity) items.push([`New ${label.toLowerCase()} inside this node…`, () => post({ type: 'create', kind, parent: id })]);
    }
    if (!id) {
      for (const [kind, label] of PALETTE[graph?.kind] || []) items.push([`New ${label.toLowerCase()}…`, () => create(kind)]);
      items.push(['Re-layout', () => post({ type: 'relayout', page: page() })]);
    }
    showMenu(event.clientX, event.clientY, items);
  });

  function showMenu(x, y, items) {
    menu.textContent = '';
    for (const [label, action] of items) {
      const item = document.createElement('div');
      item.className = 'item';
      item.setAttribute('role', 'menuitem');
      item.textContent = label;
      item.addEventListener('click', () => {
        hideMenu();
        action();
      });
      menu.append(item);
    }
    menu.hidden = items.length === 0;
    menu.style.left = `${Math.min(x, window.innerWidth - 260)}px`;
    menu.style.top = `${Math.min(y, window.innerHeight - 24 * items.length - 8)}px`;
  }

  function hideMenu() {
    menu.hidden = true;
  }

  document.addEventListener('keydown', (event) => {
    if (event.key === 'Escape') {
      hideMenu();
      cancelDrag();
      if (connecting) stopConnect();
    } else if ((event.key === 'Delete' || event.key === 'Backspace') && selected) {
      post({ type: 'delete', id: selected });
    } else if (event.key === 'F2' && selected) {
      post({ type: 'rename', id: selected });
    }
  });
  document.addEventListener('click', (event) => {
    if (!menu.contains(event.target)) hideMenu();
  });

  // The view's size: the server fits a fresh layout to its shape (`page` of gudsl/graph).
  const page = () => ({ width: Math.max(1, canvas.clientWidth), height: Math.max(1, canvas.clientHeight) });
  let resized;
  window.addEventListener('resize', () => {
    clearTimeout(resized);
    resized = setTimeout(() => post({ type: 'page', page: page() }), 300);
  });

  post({ type: 'ready', page: page() });
})();
