//! End-to-end tests of `gudsl run` on ToF pipelines (component-instance diagrams): the chapter 4
//! sample runs on lavapipe, its depth images equal the same pipeline assembled through the
//! runtime's Rust API bit for bit (ρ's restriction from the previous frame included), its
//! accuracy report shows the compensation; and bad pipelines are refused with their
//! diagnostics and exit codes: an unbound input (E0401), a black image file that does not exist
//! (E0404), an output folder that cannot be made.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/scan.rs"]
mod scan;

use std::path::Path;

use cli::{gudsl, gudsl_run as run, repo, temp_dir};
use gudsl_formats::arrays;
use gudsl_runtime::{
    sim::{simulate, Camera, Motion, Scene},
    ChainRun, Gpu, Image, Kernel, Pipeline, Shape,
};

const SAMPLE: &str = "samples/pipelines/ch4_motion_compensation.gudsl";

fn gpu() -> bool {
    std::env::var_os("GUDSL_NO_GPU").is_none()
}

/// A refused run's diagnostics (on stdout, as `gudsl check` prints them) and messages (stderr).
fn refused(args: &[&str]) -> (Option<i32>, String) {
    let (code, stdout, stderr) = run(args);
    (code, format!("{stdout}\n{stderr}"))
}

/// The sample's compensated chain through the runtime's API: frames 0 and 1's distances.
fn rust_api(gpu: &Gpu) -> Vec<Vec<f32>> {
    let camera = Camera::default();
    let motion = Motion::Translation([0.01, 0.0, 0.0]);
    let mut direction = None;
    let mut distances = Vec::new();
    for frame in 0..2 {
        let simulated = simulate(&Scene::sphere(), motion, &camera, frame);
        let mut p = Pipeline::new();
        let shape = Shape { width: 200, height: 200, planes: 8 };
        let (raw, black) = (p.source("raw", shape), p.source("black", shape));
        let raw = p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0];
        let mask = p.step(Kernel::DetectMotion { theta: 0.01 * 65535.0 }, &[raw]).unwrap()[1];
        let restriction = direction.map(|mean| (mean, 45f32.to_radians()));
        let flow = p.step(Kernel::MatchBlocks { window: 5, restriction, subpixel: false }, &[raw, mask]).unwrap()[0];
        let corrected = p.step(Kernel::CorrectRaw, &[raw, flow]).unwrap()[0];
        let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[corrected]).unwrap()[3];
        p.sink(distance).unwrap();
        p.sink(flow).unwrap();
        let out = ChainRun::new(Some(gpu), &p).run(&[simulated.raw, simulated.black]).unwrap();
        // ρ's direction for the next frame, as the pipeline computes it on the GPU.
        let mut mean = Pipeline::new();
        let flow = mean.source("flow", Shape { width: 200, height: 200, planes: 2 });
        let before = mean.source("before", Shape { width: 1, height: 1, planes: 2 });
        let step = mean.step(Kernel::MeanDirection, &[flow, before]).unwrap()[0];
        mean.sink(step).unwrap();
        let known = direction.map_or(vec![0.0, 0.0], |radians| vec![radians, 1.0]);
        let before = Image { width: 1, height: 1, planes: 2, data: known };
        let next = ChainRun::new(Some(gpu), &mean).run(&[out[1].clone(), before]).unwrap().remove(0);
        direction = (next.data[1] != 0.0).then_some(next.data[0]);
        distances.push(out[0].data.clone());
    }
    distances
}

/// The mean error (cm) of `series` over its `frames` rows of the accuracy report in `out`.
fn accuracy_mean(out: &Path, series: &str, frames: usize) -> f64 {
    let csv = std::fs::read_to_string(out.join("Accuracy/accuracy.csv")).unwrap();
    let rows: Vec<f64> = csv
        .lines()
        .filter(|l| l.contains(&format!(",{series},")))
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    assert_eq!(rows.len(), frames, "{series} in\n{csv}");
    rows.iter().sum::<f64>() / frames as f64
}

#[test]
fn the_chapter_4_sample_runs_and_equals_the_rust_api() {
    if !gpu() {
        return;
    }
    let out = temp_dir("pipeline-ch4");
    let (code, stdout, stderr) = run(&[&repo(SAMPLE), "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("ran MotionCompensationPipeline (2 frames)"), "{stdout}");
    assert!(stdout.lines().any(|l| l.starts_with("Motion ") && l.contains("ToF.MotionCompensation")), "{stdout}");
    assert!(stderr.contains("frame 2/2"), "progress: {stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "Mesa's Wayland probe on the terminal: {stderr}");

    let gpu = Gpu::for_tests().expect("an adapter");
    let expected = rust_api(&gpu);
    for (frame, expected) in expected.iter().enumerate() {
        let array = read_array(&out.join(format!("Depth/distance_{frame:04}.npy"))).unwrap();
        let (shape, values) = (array.shape, array.values);
        assert_eq!(shape, [200, 200]);
        let same = values.iter().zip(expected).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "frame {frame}: the pipeline's distances differ from the Rust API's");
    }

    let (before, after) = (accuracy_mean(&out, "Uncompensated", 2), accuracy_mean(&out, "Compensated", 2));
    assert!(after < 0.7 * before, "compensation: {before:.2} cm -> {after:.2} cm");
    for file in ["Accuracy/accuracy.svg", "Accuracy/accuracy.png", "Images/preview_0001.png", "report.json"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let distance = image::open(out.join("Images/distance_0000.png")).unwrap();
    assert_eq!(distance.color(), image::ColorType::L16);
}

#[test]
fn a_phase_calibration_is_written_used_and_refused_when_it_does_not_fit() {
    let dir = temp_dir("pipeline-ch4-calibrated");
    let calibration = dir.join("calibration.npy");
    let out =
        gudsl().args(["calibrate-phases", calibration.to_str().unwrap(), "--gain-spread", "0.02"]).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(array_header(&dir.join("calibration.npy")).unwrap().0, [8, 200, 200]);
    let out = gudsl().args(["calibrate-phases", dir.join("no/such/folder/c.npy").to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "an unwritable file");
    assert!(String::from_utf8_lossy(&out.stderr).contains("c.npy"));

    // The sample on a camera whose pixels' gains spread 2 %, with sub-pixel matching and the
    // calibration.
    let sample = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    let with = |calibration: &str| {
        let text = sample
            .replace(
                "directionRestriction = 90)",
                &format!("directionRestriction = 90, phaseCalibration = \"{calibration}\", subpixel = true)"),
            )
            .replace("frames = 6)", "frames = 6, gainSpread = 0.02)");
        assert!(text.contains("gainSpread") && text.contains("subpixel"), "the sample has changed");
        let path = dir.join("calibrated.gudsl");
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    // Of the wrong shape (E0404, at the parameter) and of another size (E0405): refused.
    arrays::write(&dir.join("flat.npy"), &[4, 30, 40], &[0.0; 4800], arrays::Dtype::F32).unwrap();
    let (code, stderr) = refused(&[&with("flat.npy"), "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("E0404") && stderr.contains("shape (8, H, W)"), "{stderr}");
    arrays::write(&dir.join("small.npy"), &[8, 30, 40], &[0.0; 9600], arrays::Dtype::F32).unwrap();
    let (code, stderr) = refused(&[&with("small.npy"), "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("E0405") && stderr.contains("calibrate for this camera"), "{stderr}");
    assert!(!dir.join("out").exists(), "nothing written for a refused pipeline");
    if !gpu() {
        return;
    }
    let compensate = |calibration: &str, out: &str| {
        let out = dir.join(out);
        let (code, stdout, stderr) = run(&[&with(calibration), "--frames", "2", "-o", out.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{stdout}\n{stderr}");
        (accuracy_mean(&out, "Uncompensated", 2), accuracy_mean(&out, "Compensated", 2))
    };
    let (before, calibrated) = compensate("calibration.npy", "calibrated");
    let (_, uncalibrated) = compensate("", "uncalibrated");
    assert!(calibrated < 0.7 * before, "calibrated, sub-pixel compensation: {before:.2} cm -> {calibrated:.2} cm");
    // Uncalibrated, the pixels' gains travel with the values the correction moves.
    assert!(calibrated < uncalibrated, "calibrated {calibrated:.2} cm, uncalibrated {uncalibrated:.2} cm");
}

/// Issue 51, item 6: the calibration fitted on recorded walls (`--from DIR`) — here the
/// simulated sweep's walls, recorded as channel files with the black image — is the one fitted
/// on the simulated walls directly; a folder that holds no wall, or too few, is refused.
#[test]
fn a_phase_calibration_is_fitted_on_recorded_walls() {
    use gudsl_runtime::phase_normalization::{PhaseCalibration, SWEEP_DISTANCES, SWEEP_REFLECTIVITIES};
    let dir = temp_dir("calibrate-recorded");
    let walls = dir.join("walls");
    std::fs::create_dir(&walls).unwrap();
    let camera = Camera { gain_spread: 0.02, ..Camera::default() };
    let (w, h) = (camera.intrinsics.width, camera.intrinsics.height);
    let channel = |image: &gudsl_runtime::Image, first: usize| -> Vec<f32> {
        (0..4).flat_map(|p| image.plane(2 * p + first).to_vec()).collect()
    };
    let mut black = None;
    for (k, &distance) in SWEEP_DISTANCES.iter().enumerate() {
        for (j, &reflectivity) in SWEEP_REFLECTIVITIES.iter().enumerate() {
            let wall = Scene { wall_distance: distance, wall_reflectivity: reflectivity, ..Scene::empty() };
            let frames: Vec<_> = (0..4).map(|f| simulate(&wall, Motion::Still, &camera, f)).collect();
            for (tap, first) in [("a", 0), ("b", 1)] {
                let data: Vec<f32> = frames.iter().flat_map(|f| channel(&f.raw, first)).collect();
                let path = walls.join(format!("wall{k}{j}_{tap}.npy"));
                arrays::write(&path, &[4, 4, h, w], &data, arrays::Dtype::U16).unwrap();
            }
            black = Some(frames[0].black.clone());
        }
    }
    let black = black.unwrap();
    for (tap, first) in [("a", 0), ("b", 1)] {
        let path = walls.join(format!("black_{tap}.npy"));
        arrays::write(&path, &[4, h, w], &channel(&black, first), arrays::Dtype::U16).unwrap();
    }
    let out = dir.join("recorded.npy");
    let made =
        gudsl().args(["calibrate-phases", out.to_str().unwrap(), "--from", walls.to_str().unwrap()]).output().unwrap();
    assert_eq!(made.status.code(), Some(0), "{}", String::from_utf8_lossy(&made.stderr));
    assert!(String::from_utf8_lossy(&made.stderr).contains("fitting on 12 wall(s)"));
    let recorded = read_array(&out).unwrap();
    assert_eq!(recorded.shape, [8, h, w]);
    let simulated = PhaseCalibration::simulated(&camera).coefficients.data;
    // The same walls, frames and black image: the same fit, but for the order of float sums.
    let worst =
        recorded.values.iter().zip(&simulated).map(|(a, b)| (a - b).abs() / b.abs().max(1.0)).fold(0.0, f32::max);
    assert!(worst < 1e-3, "relative difference {worst}");

    // Refusals: no wall, fewer than four.
    let empty = dir.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let refused = |folder: &Path| {
        let out = gudsl()
            .args(["calibrate-phases", dir.join("x.npy").to_str().unwrap(), "--from", folder.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert!(!dir.join("x.npy").exists());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    assert!(refused(&empty).contains("holds no wall"));
    for name in std::fs::read_dir(&walls).unwrap().flatten().map(|e| e.file_name().into_string().unwrap()) {
        if !name.starts_with("wall0") && !name.starts_with("black") {
            std::fs::remove_file(walls.join(name)).unwrap();
        }
    }
    assert!(refused(&walls).contains("at least 4 static recordings"));
}

/// A pipeline file in a scratch folder, `body` inside `ComponentInstanceDiagram Bad`.
fn pipeline(dir: &Path, body: &str) -> String {
    let path = dir.join("bad.gudsl");
    std::fs::write(&path, format!("ComponentInstanceDiagram Bad\n{{\n    import ToF.*;\n{body}\n}}\n")).unwrap();
    path.to_str().unwrap().to_string()
}

const CAMERA: &str = "
    Camera instantiates SimulatedCamera (frames = 1)
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Black.In.frame ]
    }";

/// The camera and a black-image correction with `values`, whose output goes nowhere (fine).
fn camera_and_black(values: &str) -> String {
    format!(
        "{CAMERA}
    Black instantiates BlackImageCorrection ({values})
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
    }}"
    )
}

#[test]
fn bad_pipelines_are_refused_with_their_diagnostics() {
    let dir = temp_dir("pipeline-bad");
    // A filter whose output goes nowhere is fine; a sink with no input is not (E0401).
    let file = pipeline(&dir, &format!("{}\n    Writer instantiates NpyWriter ( )", camera_and_black(" ")));
    let (code, stderr) = refused(&[&file, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("E0401") && stderr.contains("`Writer` receives nothing on `DepthIn.depth`"), "{stderr}");
    assert!(!dir.join("out").exists(), "nothing written for a refused pipeline");

    // A black image that does not exist (E0404, exit code 2), at its parameter.
    let file = pipeline(&dir, &camera_and_black("channelA = \"missing_a.npy\", channelB = \"missing_b.npy\""));
    let (code, stderr) = refused(&[&file, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("E0404") && stderr.contains("missing_a.npy: does not exist"), "{stderr}");
    assert!(stderr.contains("(4, H, W)"), "the expected shape: {stderr}");

    // A black image of another size than the camera's frames (E0405), in `check` and `run`.
    for name in ["black_a.npy", "black_b.npy"] {
        arrays::write(&dir.join(name), &[4, 30, 40], &[0.0; 4800], arrays::Dtype::U16).unwrap();
    }
    let file = pipeline(&dir, &camera_and_black("channelA = \"black_a.npy\", channelB = \"black_b.npy\""));
    let out = gudsl().args(["check", &file]).output().unwrap();
    let checked = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{checked}");
    assert!(
        checked.contains("E0405") && checked.contains("the black image is 40×30, the frames it is given 200×200"),
        "{checked}"
    );
    let (code, stderr) = refused(&[&file, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("E0405") && stderr.contains("cannot meet"), "{stderr}");
    assert!(!dir.join("out").exists(), "nothing written for a refused pipeline");

    if !gpu() {
        return;
    }
    // An output folder that cannot be made: a file is in its place.
    let file = pipeline(&dir, &camera_and_black(" "));
    let blocked = dir.join("blocked");
    std::fs::write(&blocked, "a file").unwrap();
    let (code, stderr) = refused(&[&file, "-o", blocked.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("not writing into the output folder") && stderr.contains("blocked"), "{stderr}");
}

/// The runtime's demodulation of `frames` through its API: each frame's distances.
fn demodulated(gpu: &Gpu, frames: &[gudsl_runtime::Image]) -> Vec<Vec<f32>> {
    let mut p = Pipeline::new();
    let raw = p.source("raw", Shape { width: frames[0].width, height: frames[0].height, planes: 8 });
    let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[3];
    p.sink(distance).unwrap();
    let mut pipeline = ChainRun::new(Some(gpu), &p);
    frames.iter().map(|frame| pipeline.run(std::slice::from_ref(frame)).unwrap().remove(0).data).collect()
}

/// `count` frames of a still simulated camera, recorded in `dir` as channel files `a.npy` and
/// `b.npy` of shape (count, 4, H, W).
fn record_still_frames(dir: &Path, count: usize) -> Vec<gudsl_runtime::Image> {
    let camera = Camera::default();
    let frames: Vec<_> = (0..count).map(|f| simulate(&Scene::sphere(), Motion::Still, &camera, f).raw).collect();
    let (w, h) = (frames[0].width, frames[0].height);
    for (name, first) in [("a.npy", 0), ("b.npy", 1)] {
        let data: Vec<f32> =
            frames.iter().flat_map(|f| (0..4).flat_map(move |p| f.plane(2 * p + first).to_vec())).collect();
        arrays::write(&dir.join(name), &[count, 4, h, w], &data, arrays::Dtype::U16).unwrap();
    }
    frames
}

#[test]
fn recorded_raw_frames_and_depth_images_run_from_files() {
    let dir = temp_dir("pipeline-files");
    // Three simulated frames recorded as channel files of shape (3, 4, H, W).
    let frames = record_still_frames(&dir, 3);
    let (w, h) = (frames[0].width, frames[0].height);
    // A depth image in millimetres as a 16-bit PNG.
    let millimetres: Vec<u16> = (0..w * h).map(|i| 500 + (i % 3000) as u16).collect();
    image::ImageBuffer::<image::Luma<u16>, _>::from_raw(w as u32, h as u32, millimetres.clone())
        .unwrap()
        .save(dir.join("depth.png"))
        .unwrap();
    let path = dir.join("files.gudsl");
    std::fs::write(
        &path,
        r#"ComponentInstanceDiagram Recorded
{
    import ToF.*;
    Recording instantiates RawFrameFile (channelA = "a.npy", channelB = "b.npy")
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }
    Demod instantiates Demodulation ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Writer.In.depth ]
    }
    Png instantiates DepthFile (path = "depth.png", scale = 0.001)
    {
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Writer.In.depth ]
    }
    Writer instantiates NpyWriter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#,
    )
    .unwrap();
    let out = dir.join("out");
    let mut args = vec![path.to_str().unwrap(), "-o", out.to_str().unwrap()];
    if !gpu() {
        args.push("--cpu");
    }
    let (code, stdout, stderr) = run(&args);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("ran Recorded (3 frames)"), "{stdout}");
    let read = |name: &str| read_array(&out.join("Writer").join(name)).unwrap().values;
    let png = read("Png_distance_0000.npy");
    assert!(png.iter().zip(&millimetres).all(|(m, &mm)| *m == mm as f32 * 0.001), "the PNG's millimetres in metres");
    assert!(!out.join("Writer/Png_distance_0001.npy").exists(), "a PNG is one frame");
    if gpu() {
        let expected = demodulated(&Gpu::for_tests().expect("an adapter"), &frames);
        for (frame, expected) in expected.iter().enumerate() {
            let got = read(&format!("Demod_distance_{frame:04}.npy"));
            assert!(got.iter().zip(expected).all(|(a, b)| a.to_bits() == b.to_bits()), "frame {frame}");
        }
    }

    // More frames than the files hold: refused at the parameter (E0404, exit code 2).
    let text =
        std::fs::read_to_string(&path).unwrap().replace("channelB = \"b.npy\"", "channelB = \"b.npy\", frames = 5");
    std::fs::write(&path, text).unwrap();
    let (code, stderr) = refused(&[path.to_str().unwrap(), "-o", dir.join("refused").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("E0404") && stderr.contains("the file holds 3 frame(s) of 200×200; 5 are asked for"),
        "{stderr}"
    );
    assert!(!dir.join("refused").exists());
}

/// The chapter 5 sample's per-pixel loop through the runtime's API: the integration time of
/// each of `frames` frames, from 8000 µs.
fn per_pixel_loop(gpu: &Gpu, frames: usize) -> Vec<f32> {
    let model = gudsl_runtime::kernels::integration::IntegrationModel::SIMULATED;
    let mut times = vec![8000.0];
    for frame in 0..frames - 1 {
        let t = *times.last().unwrap();
        let camera = Camera { integration_us: t, supersampling: 1, ..Camera::default() };
        let simulated = simulate(&Scene::plates(), Motion::Still, &camera, frame);
        let mut p = Pipeline::new();
        let shape = Shape { width: 200, height: 200, planes: 8 };
        let (raw, black) = (p.source("raw", shape), p.source("black", shape));
        let raw = p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0];
        let intensity = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[2];
        let next = p.step(Kernel::IntegrationTime { t_curr: t, model }, &[intensity]).unwrap()[0];
        p.sink(next).unwrap();
        let out = ChainRun::new(Some(gpu), &p).run(&[simulated.raw, simulated.black]).unwrap();
        times.push(out[0].data[0]);
    }
    times
}

#[test]
fn the_chapter_5_loop_settles_per_pixel_faster_than_may_and_equals_the_rust_api() {
    let out = temp_dir("pipeline-ch5");
    let mut args = vec![repo("samples/pipelines/ch5_integration_time.gudsl"), "-o".into(), out.display().to_string()];
    args.extend(["--frames".to_string(), "6".to_string()]);
    if !gpu() {
        args.push("--cpu".into());
    }
    let (code, stdout, stderr) = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let csv = std::fs::read_to_string(out.join("Accuracy/accuracy.csv")).unwrap();
    let series = |name: &str| -> Vec<(f64, f32)> {
        csv.lines()
            .filter(|l| l.contains(&format!(",{name},")))
            .map(|l| {
                let fields: Vec<&str> = l.split(',').collect();
                (fields[3].parse().unwrap(), fields[5].parse().unwrap())
            })
            .collect()
    };
    let (per_pixel, may) = (series("PerPixel"), series("MeanIntensity"));
    assert_eq!((per_pixel.len(), may.len()), (6, 6), "{csv}");
    // Both start overexposed; per pixel settles within 5 % in two frames, with an error under
    // 3 cm; May's controller is still far off.
    let settled = per_pixel[5].1;
    assert!(per_pixel[2..].iter().all(|(_, t)| (t - settled).abs() < 0.05 * settled), "{csv}");
    assert!(per_pixel[5].0 < 3.0 && may[5].0 > 2.0 * per_pixel[5].0, "{csv}");
    assert!(may[5].1 > 1.1 * settled, "{csv}");
    if gpu() {
        let expected = per_pixel_loop(&Gpu::for_tests().expect("an adapter"), 6);
        let got: Vec<f32> = per_pixel.iter().map(|(_, t)| *t).collect();
        assert_eq!(got, expected, "the loop's integration times equal the Rust API's bit for bit");
    }
}

#[test]
fn the_chapter_6_scan_accumulates_the_object_from_three_cameras() {
    let out = temp_dir("pipeline-ch6");
    let mut args = vec![repo("samples/pipelines/ch6_object_scan.gudsl"), "-o".into(), out.display().to_string()];
    if !gpu() {
        args.push("--cpu".into());
    }
    let (code, stdout, stderr) = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("LeftIcp") && stdout.contains("ToF.IcpRegistration"), "{stdout}");
    let (points, normals) = gudsl_formats::ply::read(&std::fs::read(out.join("Ply/cloud.ply")).unwrap()).unwrap();
    // Three cameras × three frames after the three of the empty scene learnt as background.
    assert!(points.len() > 9000, "{} points", points.len());
    // Segmented: no wall (at 4 m) and nothing far from the box at (0.1, 0.05, 3.0), whichever
    // camera saw it: the extrinsic poses put the views into one frame.
    let centre = [0.1, 0.05, 3.0];
    let far = points.iter().filter(|p| (0..3).map(|k| (p[k] - centre[k]).powi(2)).sum::<f32>().sqrt() > 0.8).count();
    assert!(far * 100 < points.len(), "{far} of {} points away from the box", points.len());
    let mean_x = points.iter().map(|p| p[0]).sum::<f32>() / points.len() as f32;
    assert!((mean_x - centre[0]).abs() < 0.1, "the views meet around the box: mean x {mean_x}");
    // Normals are unit vectors (zero at the silhouette, where a neighbour is missing).
    let length = |n: &[f32; 3]| (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let unit = normals.iter().filter(|n| (length(n) - 1.0).abs() < 1e-3).count();
    assert!(normals.iter().all(|n| length(n) < 1e-6 || (length(n) - 1.0).abs() < 1e-3), "unit or zero normals");
    assert!(unit * 10 > 8 * normals.len(), "{unit} of {} normals", normals.len());

    if gpu() {
        let (expected_points, expected_normals) = scan::scan(&Gpu::for_tests().expect("an adapter"), 200, 200, 6);
        assert_eq!(points.len(), expected_points.len(), "points against the Rust API's");
        assert!(points == expected_points, "the points equal the Rust API's bit for bit");
        assert!(normals == expected_normals, "the normals equal the Rust API's bit for bit");
    }
}

/// Chapter 6's sample with its three registrations bound through an `async` port of the user's
/// own component diagram (a library filter on a port of another name).
fn scan_with_async_registration(dir: &Path) -> String {
    let mut text = std::fs::read_to_string(repo("samples/pipelines/ch6_object_scan.gudsl")).unwrap();
    for side in ["Left", "Centre", "Right"] {
        let port = format!("    {side}Icp instantiates IcpRegistration ( )\n    {{\n        In : CloudIn (");
        assert!(text.contains(&port), "{side}");
        text = text.replace(&port, &port.replace("CloudIn", "AsyncCloudIn"));
    }
    text += "
ComponentDiagram AsyncRegistration
{
    filter ToF.IcpRegistration
    {
        async port AsyncCloudIn ( processor cloud : ToF.IPointCloudProcessor );
        port PoseOut ( provider pose : ToF.IPoseProvider );
    }

    filter ToF.PointCloudConversion
    {
        port CloudOut ( provider cloud : ToF.IPointCloudProvider );
        [ToAsync source CloudOut.cloud ==> target AsyncCloudIn.cloud]
    }
}
";
    let path = dir.join("scan.gudsl");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

#[test]
fn async_registrations_run_apart_and_accumulate_the_same_scan() {
    let dir = temp_dir("pipeline-ch6-async");
    let ran = |file: &str, out: &str| {
        let mut args = vec![file, "--frames", "5", "-o", out];
        if !gpu() {
            args.push("--cpu");
        }
        let (code, stdout, stderr) = run(&args);
        assert_eq!(code, Some(0), "{stdout}\n{stderr}");
        stdout
    };
    let in_order = dir.join("in-order");
    ran(&repo("samples/pipelines/ch6_object_scan.gudsl"), in_order.to_str().unwrap());
    let apart = dir.join("apart");
    let stdout = ran(&scan_with_async_registration(&dir), apart.to_str().unwrap());
    for side in ["Left", "Centre", "Right"] {
        let line = stdout.lines().find(|l| l.starts_with(&format!("{side}Icp "))).unwrap_or_default();
        assert!(line.contains("ToF.IcpRegistration (async)"), "{stdout}");
    }
    // Each registration on its thread and device while the other cameras' stages go on, its
    // pose joined where the transform needs it: the same cloud, byte for byte (before, a
    // library filter on a port of another name was given nothing).
    let (a, b) =
        (std::fs::read(in_order.join("Ply/cloud.ply")).unwrap(), std::fs::read(apart.join("Ply/cloud.ply")).unwrap());
    assert!(a.len() > 100_000 && a == b, "{} and {} bytes", a.len(), b.len());
}

/// The array at `path`, read as a run reads it (through its folder).
fn read_array(path: &std::path::Path) -> Result<arrays::Array, arrays::ArrayError> {
    arrays::read(&gudsl_files::Folder::open(path.parent().unwrap()).unwrap(), path)
}

fn array_header(path: &std::path::Path) -> Result<(Vec<usize>, arrays::Dtype), arrays::ArrayError> {
    arrays::header(&gudsl_files::Folder::open(path.parent().unwrap()).unwrap(), path)
}
