"""Chapter 4's chain as a researcher writes it in numpy, from the dissertation's equations:
motion detection (eq. 4.4, 4.5), block matching along a constant velocity over an MWS window
(eq. 4.6-4.10, ties to the shorter vector), correction of the raw channels along the flow
(sec. 4.2.5) and demodulation (eq. 2.x: phase from the four phase images, distance from the
phase). Vectorised over the image: one loop over the window's candidates, none over pixels.

python3 cpu_vs_numpy.py DIR FRAMES MWS THETA_RAW
reads DIR/a.npy and DIR/b.npy ((N, 4, H, W) uint16), writes DIR/numpy/distance_NNNN.npy per
frame and prints the steady-state milliseconds per frame (frames 1.. : the first warms up).
"""

import os
import sys
import time

import numpy as np

C = 299_792_458.0


def chain(a, b, mws, theta, modulation_hz=20e6):
    """The distance image of one frame's channels a, b ((4, H, W) float32)."""
    p = a + b  # P+_i = A_i + B_i
    motion = np.abs(p[1:] - p[0]).sum(axis=0)
    mask = motion > theta
    r = (mws - 1) // 2
    pad = 3 * r
    padded = np.pad(p, ((0, 0), (pad, pad), (pad, pad)), mode="edge")
    h, w = p.shape[1:]
    best = np.full((h, w), np.inf, dtype=np.float32)
    best_length = np.full((h, w), np.iinfo(np.int32).max)
    u = np.zeros((h, w), dtype=np.int64)
    v = np.zeros((h, w), dtype=np.int64)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            ssd = np.zeros((h, w), dtype=np.float32)
            for k in range(1, 4):
                shifted = padded[k, pad + k * dy : pad + k * dy + h, pad + k * dx : pad + k * dx + w]
                d = p[0] - shifted
                ssd += d * d
            length = dx * dx + dy * dy
            better = (ssd < best) | ((ssd == best) & (length < best_length))
            best = np.where(better, ssd, best)
            best_length = np.where(better, length, best_length)
            u = np.where(better, dx, u)
            v = np.where(better, dy, v)
    u = np.where(mask, u, 0)
    v = np.where(mask, v, 0)
    ys, xs = np.indices((h, w))
    a = a.copy()
    b = b.copy()
    for k in range(1, 4):
        yk = np.clip(ys + k * v, 0, h - 1)
        xk = np.clip(xs + k * u, 0, w - 1)
        a[k] = a[k][yk, xk]
        b[k] = b[k][yk, xk]
    q = a - b
    phase = np.arctan2(q[3] - q[1], q[0] - q[2])
    phase = np.where(phase < 0, phase + 2 * np.pi, phase)
    return (C / (2 * modulation_hz) * phase / (2 * np.pi)).astype(np.float32)


def main():
    folder, frames, mws, theta = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    a_all = np.load(os.path.join(folder, "a.npy"), mmap_mode="r")
    b_all = np.load(os.path.join(folder, "b.npy"), mmap_mode="r")
    out = os.path.join(folder, "numpy")
    os.makedirs(out, exist_ok=True)
    started = None
    for frame in range(frames):
        if frame == 1:
            started = time.perf_counter()
        a = np.asarray(a_all[frame], dtype=np.float32)
        b = np.asarray(b_all[frame], dtype=np.float32)
        np.save(os.path.join(out, f"distance_{frame:04d}.npy"), chain(a, b, mws, theta))
    print((time.perf_counter() - started) * 1000.0 / (frames - 1))


if __name__ == "__main__":
    main()
