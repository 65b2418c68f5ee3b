// The results panel's array inspector: a run's `.npy` images (distance, amplitude, intensity,
// masks) drawn with a colour map and its scale, the value under the cursor (distances in cm),
// and the difference of two (A − B, a diverging map around 0) — compensated against
// uncompensated, one setting against another; a flow field (2 planes, dx and dy) as a colour
// wheel with arrows, its vector under the cursor. Arrays are read from the run's folder as the
// panel's pictures are; a file that is no little-endian, C-ordered NumPy array says so.
(function () {
  'use strict';
  const root = document.getElementById('inspector');
  if (!root) return;
  const arrays = JSON.parse(root.dataset.arrays);
  const [first, second, mode] = ['inspect-a', 'inspect-b', 'inspect-mode'].map((id) => document.getElementById(id));
  const canvas = document.getElementById('inspect-canvas');
  const readout = document.getElementById('inspect-readout');
  const scale = document.getElementById('inspect-scale');
  const loaded = new Map(); // uri -> Promise of {width, height, values}
  let shown = null; // {width, height, values, metres}

  for (const select of [first, second]) {
    for (const a of arrays) select.append(new Option(a.name, a.uri));
  }
  // B: the same file of another sink or setting (`A/distance_0000.npy` against
  // `B/distance_0000.npy`) where there is one, else the next array.
  const base = (name) => name.split('/').pop();
  const twin = arrays.findIndex((a, i) => i > 0 && base(a.name) === base(arrays[0].name));
  if (arrays.length > 1) second.selectedIndex = twin > 0 ? twin : 1;
  for (const el of [first, second, mode]) el.addEventListener('change', () => void draw());
  canvas.addEventListener('mousemove', (event) => {
    if (!shown) return;
    const box = canvas.getBoundingClientRect();
    // Canvas pixels to array pixels: a flow is drawn at twice its size; side by side, B is
    // right of A after a gap.
    const zoom = shown.dy ? 2 : 1;
    let x = Math.floor((((event.clientX - box.left) / box.width) * canvas.width) / zoom);
    const y = Math.floor((((event.clientY - box.top) / box.height) * canvas.height) / zoom);
    let values = shown.values;
    let which = '';
    if (shown.second) {
      which = x >= shown.width ? 'B ' : 'A ';
      if (x >= shown.width) [x, values] = [x - shown.width - GAP, shown.second];
    }
    if (x < 0 || y < 0 || x >= shown.width || y >= shown.height) return;
    const i = y * shown.width + x;
    if (shown.dy) {
      const [dx, dy] = [shown.values[i], shown.dy[i]];
      const angle = (Math.atan2(dy, dx) * 180) / Math.PI;
      readout.textContent = `(${x}, ${y}): dx ${dx.toFixed(3)}, dy ${dy.toFixed(3)} px per phase image (${Math.hypot(dx, dy).toFixed(3)} px at ${angle.toFixed(0)}°)`;
      return;
    }
    readout.textContent = `${which}(${x}, ${y}): ${format(values[i], shown.metres)}`;
  });
  canvas.addEventListener('mouseleave', () => (readout.textContent = ''));
  void draw();

  function format(v, metres) {
    if (!Number.isFinite(v)) return 'no value';
    return metres ? `${(v * 100).toFixed(2)} cm` : v.toPrecision(5);
  }

  async function draw() {
    readout.textContent = '';
    try {
      const a = await load(first.value);
      const difference = mode.value === 'difference';
      const pair = mode.value === 'both';
      let values = a.values;
      let b = null;
      if (difference || pair) {
        b = await load(second.value);
        if (b.width !== a.width || b.height !== a.height) {
          throw new Error(`A is ${a.width}×${a.height}, B ${b.width}×${b.height}: they cannot be compared`);
        }
        if (difference) values = a.values.map((v, i) => v - b.values[i]);
      }
      const name = first.selectedOptions[0]?.text ?? '';
      if (a.dy && !difference) {
        shown = { width: a.width, height: a.height, values: a.values, dy: a.dy };
        return paintFlow(shown);
      }
      shown = { width: a.width, height: a.height, values, metres: /distance|depth|truth/i.test(name), second: pair ? b.values : null };
      paint(shown, difference);
    } catch (error) {
      shown = null;
      scale.textContent = String(error.message || error);
    }
  }

  function load(uri) {
    if (!loaded.has(uri)) loaded.set(uri, fetch(uri).then((r) => r.arrayBuffer()).then(parseNpy));
    return loaded.get(uri);
  }

  /** A NumPy array (.npy, versions 1–3) as its last two axes' first plane, in float; a flow's
   * second plane (shape (2, H, W): dx, dy) as `dy`. */
  function parseNpy(buffer) {
    const bytes = new Uint8Array(buffer);
    const magic = String.fromCharCode(...bytes.slice(1, 6));
    if (bytes[0] !== 0x93 || magic !== 'NUMPY') throw new Error('not a NumPy array');
    const view = new DataView(buffer);
    const long = bytes[6] >= 2;
    const headerLength = long ? view.getUint32(8, true) : view.getUint16(8, true);
    const start = (long ? 12 : 10) + headerLength;
    const header = new TextDecoder().decode(bytes.slice(long ? 12 : 10, start));
    const descr = /'descr':\s*'([<>|=]?)([fiub])(\d+)'/.exec(header);
    const shape = /'shape':\s*\(([^)]*)\)/.exec(header);
    if (!descr || !shape || /'fortran_order':\s*True/.test(header)) throw new Error('an array this inspector cannot read');
    if (descr[1] === '>') throw new Error('a big-endian array');
    const dims = shape[1].split(',').map((s) => s.trim()).filter(Boolean).map(Number);
    if (dims.length < 2) throw new Error(`an array of shape (${dims.join(', ')}): no image`);
    const [height, width] = dims.slice(-2);
    const count = width * height;
    const size = Number(descr[3]);
    const Kind = {
      f4: Float32Array, f8: Float64Array, u1: Uint8Array, u2: Uint16Array, u4: Uint32Array,
      i1: Int8Array, i2: Int16Array, i4: Int32Array, b1: Uint8Array,
    }[descr[2] + size];
    if (!Kind) throw new Error(`elements of type ${descr[2]}${size}`);
    const flow = dims.length === 3 && dims[0] === 2;
    const planes = flow ? 2 : 1;
    if (buffer.byteLength < start + planes * count * size) throw new Error('the array is shorter than its header says');
    const data = Float32Array.from(new Kind(buffer.slice(start, start + planes * count * size)));
    return { width, height, values: data.subarray(0, count), dy: flow ? data.subarray(count) : null };
  }

  /** Viridis at t in [0, 1] (its anchors every eighth, linear between). */
  const VIRIDIS = [[68, 1, 84], [72, 36, 117], [65, 68, 135], [53, 95, 141], [42, 120, 142], [33, 145, 140], [34, 168, 132], [68, 191, 112], [122, 209, 81], [189, 223, 38], [253, 231, 37]];
  function viridis(t) {
    const x = Math.min(1, Math.max(0, t)) * (VIRIDIS.length - 1);
    const i = Math.min(VIRIDIS.length - 2, Math.floor(x));
    const f = x - i;
    return VIRIDIS[i].map((c, k) => Math.round(c + (VIRIDIS[i + 1][k] - c) * f));
  }
  /** Blue (−) through white (0) to red (+), t in [−1, 1]. */
  function diverging(t) {
    const s = Math.min(1, Math.abs(t));
    return t < 0 ? [Math.round(255 * (1 - s)), Math.round(255 * (1 - s)), 255] : [255, Math.round(255 * (1 - s)), Math.round(255 * (1 - s))];
  }

  /** A flow field as a colour wheel (hue the direction, brightness the length up to its 99th
   * percentile) with an arrow every 8 pixels where something moved. */
  function paintFlow({ width, height, values, dy }) {
    const lengths = values.map((dx, i) => Math.hypot(dx, dy[i]));
    const sorted = Float32Array.from(lengths).filter((l) => l > 0).sort();
    const top = sorted.length ? sorted[Math.floor(0.99 * (sorted.length - 1))] : 1;
    canvas.width = width * 2;
    canvas.height = height * 2;
    const context = canvas.getContext('2d');
    const image = context.createImageData(width, height);
    values.forEach((dx, i) => {
      const [r, g, b] = wheel(Math.atan2(dy[i], dx), Math.min(1, lengths[i] / top));
      image.data.set([r, g, b, 255], i * 4);
    });
    // Drawn at twice its size, so the arrows have room.
    const small = new OffscreenCanvas(width, height);
    small.getContext('2d').putImageData(image, 0, 0);
    context.imageSmoothingEnabled = false;
    context.drawImage(small, 0, 0, width * 2, height * 2);
    context.strokeStyle = 'white';
    context.lineWidth = 1;
    const step = 8;
    for (let y = step / 2; y < height; y += step) {
      for (let x = step / 2; x < width; x += step) {
        const i = y * width + x;
        if (!(lengths[i] > 0)) continue;
        const reach = (Math.min(1, lengths[i] / top) * step * 2 - 1) / lengths[i];
        const [x0, y0, x1, y1] = [x * 2, y * 2, x * 2 + values[i] * reach, y * 2 + dy[i] * reach];
        context.beginPath();
        context.moveTo(x0, y0);
        context.lineTo(x1, y1);
        const head = Math.atan2(y1 - y0, x1 - x0);
        for (const side of [-0.5, 0.5]) context.lineTo(x1 - 4 * Math.cos(head + side), y1 - 4 * Math.sin(head + side));
        context.stroke();
      }
    }
    canvas.style.width = `${width * 2}px`;
    scale.textContent = `flow: up to ${top.toFixed(3)} px per phase image at full brightness; hue the direction (red right, yellow-green down, cyan left, blue-violet up), black where nothing moved`;
  }

  /** The colour wheel's colour of a direction (radians, y down) at a brightness. */
  function wheel(angle, value) {
    const hue = ((angle / (2 * Math.PI)) * 360 + 360) % 360;
    const f = (n) => {
      const k = (n + hue / 60) % 6;
      return value * (1 - Math.max(0, Math.min(k, 4 - k, 1)));
    };
    return [f(5), f(3), f(1)].map((c) => Math.round(c * 255));
  }

  /** The pixels between A and B side by side. */
  const GAP = 4;

  /** An image (and, side by side, B on the same scale) with its colour map. */
  function paint({ width, height, values, metres, second }, difference) {
    // The range of the values that are there: a distance of 0 is "no value" (the invalid pixels).
    const present = (v) => Number.isFinite(v) && !(metres && !difference && v === 0);
    let low = Infinity;
    let high = -Infinity;
    for (const v of second ? [...values, ...second] : values) {
      if (!present(v)) continue;
      low = Math.min(low, v);
      high = Math.max(high, v);
    }
    const bound = Math.max(Math.abs(low), Math.abs(high)) || 1;
    canvas.width = second ? width * 2 + GAP : width;
    canvas.height = height;
    const context = canvas.getContext('2d');
    context.clearRect(0, 0, canvas.width, canvas.height);
    for (const [k, plane] of (second ? [values, second] : [values]).entries()) {
      const image = context.createImageData(width, height);
      plane.forEach((v, i) => {
        const [r, g, b] = !present(v) ? [128, 128, 128] : difference ? diverging(v / bound) : viridis((v - low) / (high - low || 1));
        image.data.set([r, g, b, 255], i * 4);
      });
      context.putImageData(image, k * (width + GAP), 0);
    }
    const shownWidth = Math.max(canvas.width, Math.min(second ? 960 : 640, canvas.width * 2));
    canvas.style.width = `${shownWidth}px`;
    const range = difference ? [-bound, bound] : [low, high];
    scale.textContent = Number.isFinite(range[0])
      ? `${difference ? 'A − B' : second ? 'A | B' : first.selectedOptions[0]?.text}: ${format(range[0], metres)} … ${format(range[1], metres)}${difference ? ' (blue: A < B, red: A > B)' : ''}; grey: no value`
      : 'no values';
  }
})();
