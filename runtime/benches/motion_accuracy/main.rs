//! The accuracy benchmark of chapter 4 (Tables 4.1–4.3) on the simulated camera, with the
//! dissertation's figures beside: for a sphere (off the optical axis), a box and a bunny (dark
//! objects, reflectivity 0.3, before the wall's 0.8) and the low-contrast relief (0.6), each
//! translated 1 cm or turned 1° about the line of sight per phase image, the error before and
//! after motion compensation — per pixel (radial) and as a cloud (cloud-to-model, as Tables
//! 4.1–4.3 measure it) on the foreground the camera measured nearer than 3.85 m. The grid of
//! Tables 4.2/4.3 (MWS, NH, θ, ρ), then at the default parameters: without phase normalization,
//! normalised for the matching only, the NH filter's linear and circular median, and the literal
//! method against the improved one (sub-pixel), with times.
//!
//! As in the dissertation's simulator: no white noise, flying pixels on; the pixels' gains
//! spread 2 % (which phase normalization undoes). The static reference is the camera standing
//! still where each frame's first phase image was taken: the view compensation reconstructs.
//! Frames 1–3 of each sequence are scored; ρ restricts around the previous frame's mean
//! direction. Runs on the GPU when there is one (lavapipe included), else on the CPU reference;
//! times are the median of 5 whole-pipeline runs (upload, every step, readback).
//!
//! `cargo bench -p gudsl-runtime --bench motion_accuracy [-- scene-filter]`

mod dissertation;
mod scoring;

use std::time::Instant;

use dissertation::{Reference, Row, BUDDHA, DEFAULT, DEFAULT_WITH_NH, DRAGON, GRID, UNRESTRICTED};
use gudsl_runtime::kernels::motion::{angle_of, correct_raw, mean_direction};
use gudsl_runtime::kernels::tof::{demodulate, subtract_black};
use gudsl_runtime::phase_normalization::PhaseCalibration;
use gudsl_runtime::sim::{simulate, standing_at, Camera, Frame, Motion, Object, Scene};
use gudsl_runtime::{ChainRun, Gpu, Image, Kernel, Pipeline, Shape};
use scoring::{Score, Truth};

const MODULATION_HZ: f32 = 20.0e6;
const FRAMES: usize = 4;
const TIMING_RUNS: usize = 5;

/// How the flow directions are smoothed.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Nh {
    Off,
    /// The runtime's NH filter: the circular median.
    Circular,
    /// The linear median of angles in [0, 2π) the runtime had before (CPU, for comparison).
    Linear,
}

/// Where phase normalization is applied.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Normalization {
    Off,
    /// Matching reads the normalised frame, the correction moves the raw one (the runtime before).
    MatchingOnly,
    /// Matching reads, and the correction moves, the normalised frame (the runtime's).
    Full,
}

/// One way to compensate.
#[derive(Debug, Clone, Copy)]
struct Method {
    row: Row,
    nh: Nh,
    normalization: Normalization,
    /// The improved method: the flow refined to a quarter pixel.
    subpixel: bool,
}

impl Method {
    fn literal(row: Row) -> Method {
        Method {
            row,
            nh: if row.smooth { Nh::Circular } else { Nh::Off },
            normalization: Normalization::Full,
            subpixel: false,
        }
    }
}

/// A scene in motion: its frames, their truth, and the dissertation's scene it stands beside.
struct Sequence {
    name: String,
    reference: &'static Reference,
    frames: Vec<Frame>,
    truths: Vec<Truth>,
    still: Vec<Frame>,
    still_truths: Vec<Truth>,
}

impl Sequence {
    fn new(name: &str, scene: Scene, motion: Motion, camera: &Camera) -> Sequence {
        let (mut frames, mut truths, mut still, mut still_truths) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for k in 0..FRAMES {
            let frame = simulate(&scene, motion, camera, k);
            // The static reference sees what this frame's first phase image saw: the view
            // compensation reconstructs.
            let standing = standing_at(camera, motion, 4 * k);
            let frame_still = simulate(&scene, Motion::Still, &standing, k);
            if k > 0 {
                truths.push(Truth::new(&scene, motion, camera, k, frame.truth.clone()));
                still_truths.push(Truth::new(&scene, Motion::Still, &standing, k, frame_still.truth.clone()));
            }
            frames.push(frame);
            still.push(frame_still);
        }
        let reference = if matches!(motion, Motion::Rotation(_)) { &DRAGON } else { &BUDDHA };
        Sequence { name: name.to_string(), reference, frames, truths, still, still_truths }
    }
}

fn uncompensated(frame: &Frame) -> Image {
    let [.., distance] = demodulate(&subtract_black(&frame.raw, &frame.black), MODULATION_HZ);
    distance
}

/// The runtime's pipeline for `method`: black subtraction → [normalization] → detection →
/// matching → [NH] → correction of the (normalised) frame → demodulation. Sinks: the
/// distance and the flow; with the linear NH, the flow and the frame to correct (finished on the CPU).
fn pipeline(method: &Method, restriction: Option<(f32, f32)>, shape: Shape) -> Pipeline {
    let mut p = Pipeline::new();
    let (raw, black) = (p.source("raw", shape), p.source("black", shape));
    let raw = p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0];
    let normalized = if method.normalization != Normalization::Off {
        let calibration = p.source("calibration", shape);
        p.step(Kernel::NormalizePhases, &[raw, calibration]).unwrap()[0]
    } else {
        raw
    };
    let theta = method.row.theta_percent / 100.0 * 65535.0;
    let mask = p.step(Kernel::DetectMotion { theta }, &[normalized]).unwrap()[1];
    let window = method.row.window;
    let mut flow =
        p.step(Kernel::MatchBlocks { window, restriction, subpixel: method.subpixel }, &[normalized, mask]).unwrap()[0];
    if method.nh == Nh::Linear {
        p.sink(flow).unwrap();
        p.sink(normalized).unwrap();
        return p;
    }
    if method.nh == Nh::Circular {
        flow = p.step(Kernel::SmoothFlow { window }, &[flow]).unwrap()[0];
    }
    let moved = if method.normalization == Normalization::Full { normalized } else { raw };
    let corrected = p.step(Kernel::CorrectRaw, &[moved, flow]).unwrap()[0];
    let distance = p.step(Kernel::Demodulate { modulation_hz: MODULATION_HZ }, &[corrected]).unwrap()[3];
    p.sink(distance).unwrap();
    p.sink(flow).unwrap();
    p
}

/// The NH filter as it was: the median of the neighbours' angles in [0, 2π), sorted linearly.
fn smooth_flow_linear(flow: &Image, window: u32) -> Image {
    let (w, h, n) = (flow.width as isize, flow.height as isize, flow.pixels());
    let r = (window as isize - 1) / 2;
    let mut out = flow.clone();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let (u, v) = (flow.data[i], flow.data[n + i]);
            if u == 0.0 && v == 0.0 {
                continue;
            }
            let mut angles: Vec<f32> = (-r..=r)
                .flat_map(|dy| (-r..=r).map(move |dx| (x + dx, y + dy)))
                .filter(|&(nx, ny)| nx >= 0 && ny >= 0 && nx < w && ny < h)
                .map(|(nx, ny)| (ny * w + nx) as usize)
                .filter(|&j| flow.data[j] != 0.0 || flow.data[n + j] != 0.0)
                .map(|j| angle_of(flow.data[j], flow.data[n + j]))
                .collect();
            angles.sort_by(f32::total_cmp);
            let (median, length) = (angles[angles.len() / 2], (u * u + v * v).sqrt());
            out.data[i] = (length * median.cos()).round();
            out.data[n + i] = (length * median.sin()).round();
        }
    }
    out
}

/// Compensates every frame of `sequence` with `method`: the scores of frames 1–3, their mean
/// flow direction (degrees) and the median time of a frame (ms; none for the CPU-finished
/// linear NH).
fn compensate(
    gpu: Option<&Gpu>,
    method: &Method,
    sequence: &Sequence,
    calibration: &Image,
) -> (Score, f64, Option<f64>) {
    let (mut scores, mut directions, mut time) = (Vec::new(), Vec::new(), None);
    let mut previous: Option<f32> = None;
    for (k, frame) in sequence.frames.iter().enumerate() {
        let restriction = method.row.rho.zip(previous).map(|(rho, mean)| (mean, (rho / 2.0).to_radians()));
        let shape = Shape { width: frame.raw.width, height: frame.raw.height, planes: 8 };
        let mut prepared = ChainRun::new(gpu, &pipeline(method, restriction, shape));
        let mut sources = vec![frame.raw.clone(), frame.black.clone()];
        if method.normalization != Normalization::Off {
            sources.push(calibration.clone());
        }
        let out = prepared.run(&sources).unwrap();
        let (distance, flow) = if method.nh == Nh::Linear {
            let flow = smooth_flow_linear(&out[0], method.row.window);
            let [.., distance] = demodulate(&correct_raw(&out[1], &flow), MODULATION_HZ);
            (distance, flow)
        } else {
            (out[0].clone(), out[1].clone())
        };
        previous = mean_direction(&flow);
        if k == 0 {
            continue;
        }
        if k == 1 && method.nh != Nh::Linear {
            let mut samples: Vec<f64> = (0..TIMING_RUNS)
                .map(|_| {
                    let start = Instant::now();
                    prepared.run(&sources).unwrap();
                    start.elapsed().as_secs_f64() * 1e3
                })
                .collect();
            samples.sort_by(f64::total_cmp);
            time = Some(samples[TIMING_RUNS / 2]);
        }
        scores.push(sequence.truths[k - 1].score(&distance));
        directions.push(previous.unwrap_or(0.0).to_degrees() as f64);
    }
    (Score::average(&scores), directions.iter().sum::<f64>() / directions.len() as f64, time)
}

fn reduction(before: f64, after: f64) -> String {
    format!("{:+.0} %", (after - before) / before * 100.0)
}

fn time_text(time: Option<f64>) -> String {
    time.map_or("-".into(), |t| format!("{t:.2}"))
}

fn main() {
    let filter = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let gpu = Gpu::new().map_err(|e| eprintln!("{e}; running the CPU reference")).ok();
    let device = gpu.as_ref().map_or("CPU reference".to_string(), Gpu::describe);
    let camera = Camera { noise: false, gain_spread: 0.02, ..Camera::default() };
    let calibration = PhaseCalibration::simulated(&Camera { noise: true, ..camera }).coefficients;
    let dark = |scene: Scene| Scene { object_reflectivity: 0.3, ..scene };
    let scenes = [
        // Off the optical axis, so that turning about it moves the sphere's outline.
        ("sphere", dark(Scene::wall_and(Object::Sphere { centre: [0.3, 0.1, 3.0], radius: 0.4 }))),
        ("box", dark(Scene::cuboid())),
        ("bunny", dark(Scene::bunny())),
        ("relief (low contrast)", Scene::height_field()),
    ];
    let motions = [("translation 1 cm", Motion::Translation([0.01, 0.0, 0.0])), ("rotation 1°", Motion::Rotation(1.0))];
    println!("Motion compensation on the simulated PMD camera ({device}).");
    println!("Errors in cm on the measured foreground (< 3.85 m): radial per pixel / cloud-to-model (C2M).\n");
    let mut sequences = Vec::new();
    for (scene_name, scene) in scenes {
        for (motion_name, motion) in motions {
            let name = format!("{scene_name}, {motion_name}");
            if filter.as_ref().is_none_or(|f| name.contains(f.as_str())) {
                sequences.push(Sequence::new(&name, scene, motion, &camera));
            }
        }
    }
    println!("Table 4.1: before compensation (mean ± σ, cm)\n");
    println!("| scene | static radial | static C2M | moving radial | moving C2M | dissertation static | dissertation moving |");
    println!("|---|---|---|---|---|---|---|");
    let mut before = Vec::new();
    for s in &sequences {
        let score = |frames: &[Frame], truths: &[Truth]| {
            Score::average(&frames[1..].iter().zip(truths).map(|(f, t)| t.score(&uncompensated(f))).collect::<Vec<_>>())
        };
        let (still, moving) = (score(&s.still, &s.still_truths), score(&s.frames, &s.truths));
        let r = s.reference;
        println!(
            "| {} | {:.2} ± {:.2} | {:.2} ± {:.2} | {:.2} ± {:.2} | {:.2} ± {:.2} | {} {:.2} ± {:.2} | {:.2} ± {:.2} |",
            s.name,
            still.radial.mean,
            still.radial.sigma,
            still.c2m.mean,
            still.c2m.sigma,
            moving.radial.mean,
            moving.radial.sigma,
            moving.c2m.mean,
            moving.c2m.sigma,
            r.name,
            r.static_error.0,
            r.static_error.1,
            r.dynamic_error.0,
            r.dynamic_error.1
        );
        before.push((still, moving));
    }
    let mut summaries = Vec::new();
    for (s, (still, moving)) in sequences.iter().zip(&before) {
        let r = s.reference;
        println!("\nTable 4.2/4.3 grid: {} (beside: the {}; C2M mean ± σ in cm, time in ms)\n", s.name, r.name);
        println!("| MWS | NH | θ % | ρ ° | radial | C2M | φ ° | time | {} C2M | {} time |", r.name, r.name);
        println!("|---|---|---|---|---|---|---|---|---|---|");
        let mut best = (f64::INFINITY, 0usize);
        let mut grid = Vec::new();
        for (index, row) in GRID.iter().enumerate() {
            let (score, phi, time) = compensate(gpu.as_ref(), &Method::literal(*row), s, &calibration);
            if score.c2m.mean < best.0 {
                best = (score.c2m.mean, index);
            }
            let (m, sg, t) = r.rows[index];
            println!(
                "| {} | {} | {:.0} | {} | {:.2} ± {:.2} | {:.2} ± {:.2} | {} | {} | {m:.2} ± {sg:.2} | {t:.2} |",
                row.window,
                if row.smooth { "x" } else { "-" },
                row.theta_percent,
                row.rho.map_or("-".into(), |rho| format!("{rho:.0}")),
                score.radial.mean,
                score.radial.sigma,
                score.c2m.mean,
                score.c2m.sigma,
                row.rho.map_or("-".into(), |_| format!("{phi:.1}")),
                time_text(time)
            );
            grid.push((score, time));
        }
        let variants = [
            ("without normalization", Method { normalization: Normalization::Off, ..Method::literal(GRID[DEFAULT]) }),
            (
                "normalised for matching only",
                Method { normalization: Normalization::MatchingOnly, ..Method::literal(GRID[DEFAULT]) },
            ),
            ("NH linear median", Method { nh: Nh::Linear, ..Method::literal(GRID[DEFAULT_WITH_NH]) }),
            ("NH circular median", Method::literal(GRID[DEFAULT_WITH_NH])),
            ("improved: sub-pixel", Method { subpixel: true, ..Method::literal(GRID[DEFAULT]) }),
            ("improved: sub-pixel, MWS 7 θ 0", Method { subpixel: true, ..Method::literal(GRID[UNRESTRICTED]) }),
            (
                "MWS 7 θ 0, without normalization",
                Method { normalization: Normalization::Off, ..Method::literal(GRID[UNRESTRICTED]) },
            ),
            (
                "MWS 7 θ 0, normalised for matching only",
                Method { normalization: Normalization::MatchingOnly, ..Method::literal(GRID[UNRESTRICTED]) },
            ),
        ];
        // The labels say which column each is; the summary takes them in this order.
        let variant_scores: Vec<(Score, Option<f64>)> = variants
            .iter()
            .map(|(_, method)| {
                let (score, _, time) = compensate(gpu.as_ref(), method, s, &calibration);
                (score, time)
            })
            .collect();
        summaries.push((s, *still, *moving, grid[DEFAULT], grid[UNRESTRICTED], grid[best.1], best.1, variant_scores));
    }
    println!("\nSummary (C2M mean in cm, change against the moving scene; default: MWS 5, θ 1 %, normalised)\n");
    println!("| scene | static | moving | default | best row | default, not normalised | default, normalised for matching only | MWS 7 θ 0: not normalised / for matching only / normalised | NH linear | NH circular | improved | improved MWS 7 θ 0 | motion's error removed: default / improved MWS 7 θ 0 | ms: default / improved; MWS 7 θ 0: literal / improved |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (s, still, moving, default, mws7, best, best_index, variants) in &summaries {
        let cell = |score: &Score| format!("{:.2} ({})", score.c2m.mean, reduction(moving.c2m.mean, score.c2m.mean));
        let row = GRID[*best_index];
        // The share of what the motion added (moving − static) that compensation takes away.
        let removed = |score: &Score| {
            format!("{:.0} %", (moving.c2m.mean - score.c2m.mean) / (moving.c2m.mean - still.c2m.mean) * 100.0)
        };
        println!(
            "| {} | {:.2} | {:.2} | {} | {} MWS {} {}θ {:.0} ρ {} | {} | {} | {:.2} / {:.2} / {:.2} | {} | {} | {} | {} | {} / {} | {} / {}; {} / {} |",
            s.name,
            still.c2m.mean,
            moving.c2m.mean,
            cell(&default.0),
            cell(&best.0),
            row.window,
            if row.smooth { "NH " } else { "" },
            row.theta_percent,
            row.rho.map_or("-".into(), |r| format!("{r:.0}")),
            cell(&variants[0].0),
            cell(&variants[1].0),
            variants[6].0.c2m.mean,
            variants[7].0.c2m.mean,
            mws7.0.c2m.mean,
            cell(&variants[2].0),
            cell(&variants[3].0),
            cell(&variants[4].0),
            cell(&variants[5].0),
            removed(&default.0),
            removed(&variants[5].0),
            time_text(default.1),
            time_text(variants[4].1),
            time_text(mws7.1),
            time_text(variants[5].1)
        );
    }
    println!("\nThe dissertation: buddha 5.96 → 1.14 cm (−81 %), dragon 7.75 → 2.07 cm (−73 %), best rows.");
}
