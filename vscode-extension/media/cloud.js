// The results panel's point cloud view: a run's `.ply` clouds (binary little-endian or ASCII,
// as any PLY writer writes them) drawn in 3D on a canvas — drag to orbit, wheel to zoom, double
// click to reset — coloured by depth (z in the camera's frame) or by height (y), with the
// cloud's size. Read from the run's folder as the panel's pictures are.
(function () {
  'use strict';
  const root = document.getElementById('clouds');
  if (!root) return;
  const clouds = JSON.parse(root.dataset.clouds);
  const [select, colour] = ['cloud-file', 'cloud-colour'].map((id) => document.getElementById(id));
  const canvas = document.getElementById('cloud-canvas');
  const info = document.getElementById('cloud-info');
  const loaded = new Map();
  const view = { yaw: Math.PI, pitch: 0.35, zoom: 1 }; // looking from the cameras at the scene
  let cloud = null; // {points: Float32Array (x y z …), centre, radius}

  for (const c of clouds) select.append(new Option(c.name, c.uri));
  select.addEventListener('change', () => void show());
  colour.addEventListener('change', paint);
  let dragging = null;
  canvas.addEventListener('pointerdown', (e) => {
    dragging = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!dragging) return;
    view.yaw += (e.clientX - dragging.x) * 0.01;
    view.pitch = Math.max(-1.5, Math.min(1.5, view.pitch + (e.clientY - dragging.y) * 0.01));
    dragging = { x: e.clientX, y: e.clientY };
    paint();
  });
  canvas.addEventListener('pointerup', () => (dragging = null));
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    view.zoom = Math.max(0.1, Math.min(20, view.zoom * Math.exp(-e.deltaY * 0.001)));
    paint();
  });
  canvas.addEventListener('dblclick', () => {
    Object.assign(view, { yaw: Math.PI, pitch: 0.35, zoom: 1 });
    paint();
  });
  void show();

  async function show() {
    try {
      if (!loaded.has(select.value)) loaded.set(select.value, fetch(select.value).then((r) => r.arrayBuffer()).then(parsePly));
      cloud = await loaded.get(select.value);
      paint();
    } catch (error) {
      cloud = null;
      info.textContent = String(error.message || error);
    }
  }

  /** A PLY file's vertices (x, y, z), its centre and radius. */
  function parsePly(buffer) {
    const bytes = new Uint8Array(buffer);
    const head = new TextDecoder().decode(bytes.slice(0, Math.min(bytes.length, 4096)));
    const end = head.indexOf('end_header');
    if (!head.startsWith('ply') || end < 0) throw new Error('not a PLY file');
    const lines = head.slice(0, end).split(/\r?\n/).map((l) => l.trim());
    const format = (lines.find((l) => l.startsWith('format ')) || '').split(/\s+/)[1];
    let count = 0;
    const props = [];
    let inVertex = false;
    for (const line of lines) {
      const w = line.split(/\s+/);
      if (w[0] === 'element') {
        inVertex = w[1] === 'vertex';
        if (inVertex) count = Number(w[2]);
        else if (count) break; // vertices first, as writers put them
      } else if (w[0] === 'property' && inVertex) {
        if (w[1] === 'list') throw new Error('a vertex property that is a list');
        props.push({ type: w[1], name: w[2] });
      }
    }
    const [ix, iy, iz] = ['x', 'y', 'z'].map((n) => props.findIndex((p) => p.name === n));
    if (ix < 0 || iy < 0 || iz < 0) throw new Error('vertices without x, y, z');
    const points = new Float32Array(count * 3);
    let start = end + 'end_header'.length;
    while (bytes[start] !== 0x0a && start < bytes.length) start++;
    start++;
    if (format === 'ascii') {
      const rows = new TextDecoder().decode(bytes.slice(start)).split(/\r?\n/);
      for (let i = 0; i < count; i++) {
        const v = rows[i].trim().split(/\s+/).map(Number);
        points.set([v[ix], v[iy], v[iz]], i * 3);
      }
    } else if (format === 'binary_little_endian') {
      const SIZE = { char: 1, uchar: 1, int8: 1, uint8: 1, short: 2, ushort: 2, int16: 2, uint16: 2, int: 4, uint: 4, int32: 4, uint32: 4, float: 4, float32: 4, double: 8, float64: 8 };
      const offsets = [];
      let stride = 0;
      for (const p of props) {
        if (!SIZE[p.type]) throw new Error(`a vertex property of type ${p.type}`);
        offsets.push(stride);
        stride += SIZE[p.type];
      }
      if (bytes.length < start + stride * count) throw new Error('the file is shorter than its header says');
      const data = new DataView(buffer, start);
      const read = (k, i) => {
        const at = i * stride + offsets[k];
        return props[k].type.startsWith('double') || props[k].type === 'float64' ? data.getFloat64(at, true) : data.getFloat32(at, true);
      };
      for (let i = 0; i < count; i++) points.set([read(ix, i), read(iy, i), read(iz, i)], i * 3);
    } else {
      throw new Error(`a PLY file in ${format}`);
    }
    const centre = [0, 1, 2].map((k) => points.filter((_, i) => i % 3 === k).reduce((a, b) => a + b, 0) / Math.max(1, count));
    let radius = 0;
    for (let i = 0; i < count; i++) radius = Math.max(radius, Math.hypot(points[i * 3] - centre[0], points[i * 3 + 1] - centre[1], points[i * 3 + 2] - centre[2]));
    return { points, count, centre, radius: radius || 1 };
  }

  function paint() {
    if (!cloud) return;
    const { points, count, centre, radius } = cloud;
    const context = canvas.getContext('2d');
    const [w, h] = [canvas.width, canvas.height];
    context.fillStyle = '#111';
    context.fillRect(0, 0, w, h);
    const [cy, sy, cp, sp] = [Math.cos(view.yaw), Math.sin(view.yaw), Math.cos(view.pitch), Math.sin(view.pitch)];
    const distance = radius * 3;
    const focal = (Math.min(w, h) / 2) * view.zoom * 2.5;
    const byHeight = colour.value === 'height';
    const projected = [];
    let [low, high] = [Infinity, -Infinity];
    for (let i = 0; i < count; i++) {
      const [x, y, z] = [points[i * 3] - centre[0], points[i * 3 + 1] - centre[1], points[i * 3 + 2] - centre[2]];
      // Orbit: yaw about y, then pitch about x; the eye looks down +z from `distance` away.
      const x1 = cy * x + sy * z;
      const z1 = -sy * x + cy * z;
      const y2 = cp * y - sp * z1;
      const z2 = sp * y + cp * z1 + distance;
      if (z2 <= radius * 0.05) continue;
      const value = byHeight ? points[i * 3 + 1] : points[i * 3 + 2];
      low = Math.min(low, value);
      high = Math.max(high, value);
      projected.push([w / 2 + (focal * x1) / z2, h / 2 + (focal * y2) / z2, z2, value]);
    }
    projected.sort((a, b) => b[2] - a[2]); // far first
    for (const [x, y, , value] of projected) {
      const t = (value - low) / (high - low || 1);
      context.fillStyle = `hsl(${Math.round(240 - 240 * t)}, 90%, 55%)`;
      context.fillRect(x - 1, y - 1, 2, 2);
    }
    info.textContent = `${count} points, ${(radius * 2).toFixed(2)} m across; colour: ${byHeight ? 'height y' : 'depth z'} ${low.toFixed(2)} … ${high.toFixed(2)} m (blue to red); drag to orbit, wheel to zoom, double click to reset`;
  }
})();
