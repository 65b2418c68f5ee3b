//! Chapter 6's object scan (`samples/pipelines/ch6_object_scan.gudsl`) assembled on the
//! runtime's API, as a Rust programmer writes it: per camera the chains built once (learning the
//! background, segmenting into a cloud, the ICP reduction, the transform into the model's frame)
//! and run frame after frame, only the frame's raw data uploaded. What the end-to-end test
//! compares the pipeline's cloud with, and what the benchmark times it against.

#![allow(dead_code)] // the test and the benchmark each take what they need

use gudsl_formats::ply::Points;
use gudsl_runtime::{
    camera::{compose, pose_from, Intrinsics, Pose, IDENTITY},
    kernels::car::background,
    registration::{iterate, valid_points, IcpSettings, RegistrationError},
    sim::{simulate, Camera, Motion, Scene},
    ChainRun, Gpu, Image, Kernel, Pipeline, Shape, Slot,
};

/// The frames of the empty scene learnt as background.
pub const LEARNING_FRAMES: usize = 3;

/// The sample's three cameras: (x, yaw in degrees).
pub const CAMERAS: [(f64, f64); 3] = [(-0.5, 11.3), (0.1, 0.0), (0.7, -11.3)];

/// One camera of the scan and its chains.
pub struct ScanCamera<'g> {
    gpu: &'g Gpu,
    camera: Camera,
    extrinsic: Pose,
    learn: ChainRun<'g>,
    scan: ChainRun<'g>,
    icp: ChainRun<'g>,
    transform: ChainRun<'g>,
    settings: IcpSettings,
    learnt: Vec<(Image, Image)>,
    background: Option<(Image, Image)>,
    model: Option<(Image, Image)>,
    pose: Pose,
    increment: Pose,
}

impl<'g> ScanCamera<'g> {
    /// The camera at `x` metres, turned `yaw` degrees, of `width × height` pixels.
    pub fn new(gpu: &'g Gpu, (x, yaw): (f64, f64), width: usize, height: usize) -> ScanCamera<'g> {
        let pose = pose_from([0.0, yaw.to_radians(), 0.0], [x, 0.0, 0.0]);
        let intrinsics = Intrinsics::camcube_at(width, height);
        let shape = Shape { width, height, planes: 8 };
        let (plane, three) = (Shape { planes: 1, ..shape }, Shape { planes: 3, ..shape });

        let filtered = |p: &mut Pipeline| {
            let sources = [p.source("raw", shape), p.source("black", shape)];
            let raw = p.step(Kernel::SubtractBlack, &sources).unwrap()[0];
            let demodulated = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap();
            let distance = p.step(Kernel::Median { radius: 2 }, &[demodulated[3]]).unwrap()[0];
            let distance = p.step(Kernel::Gaussian { sigma: 2.0 }, &[distance]).unwrap()[0];
            let distance = p.step(Kernel::RemoveOutliers { range: 0.05, min_similar: 3 }, &[distance]).unwrap()[0];
            (sources, demodulated[2], distance)
        };
        let mut p = Pipeline::new();
        let (_, intensity, distance) = filtered(&mut p);
        p.sink(intensity).unwrap();
        p.sink(distance).unwrap();
        let learn = ChainRun::new(Some(gpu), &p);

        let mut p = Pipeline::new();
        let (_, intensity, distance) = filtered(&mut p);
        let (bi, bd, rays) = (p.source("bi", plane), p.source("bd", plane), p.source("rays", three));
        let segment = Kernel::Segment { theta_intensity: 100.0, theta_distance: 0.3 };
        let mut mask = p.step(segment, &[intensity, distance, bi, bd]).unwrap()[0];
        for dilate in [false, true, true, false] {
            mask = p.step(Kernel::Morphology { radius: 1, dilate }, &[mask]).unwrap()[0];
        }
        let distance = p.step(Kernel::ApplyMask, &[distance, mask]).unwrap()[0];
        let points = p.step(Kernel::PointCloud, &[distance, rays]).unwrap()[0];
        let normals = p.step(Kernel::Normals, &[points]).unwrap()[0];
        p.sink(points).unwrap();
        p.sink(normals).unwrap();
        let scan = ChainRun::new(Some(gpu), &p);

        let settings =
            IcpSettings { max_distance: 0.2, max_angle_degrees: 20.0, max_iterations: 20, ..IcpSettings::default() };
        let mut p = Pipeline::new();
        let clouds: Vec<Slot> =
            ["points", "normals", "model points", "model normals"].map(|n| p.source(n, three)).into();
        let sums = p.step(reduce(&settings, intrinsics, &IDENTITY), &clouds).unwrap()[0];
        p.sink(sums).unwrap();
        let icp = ChainRun::new(Some(gpu), &p);

        let mut p = Pipeline::new();
        let (at, facing) = (p.source("points", three), p.source("normals", three));
        let moved = p.step(Kernel::TransformPoints { pose: IDENTITY }, &[at]).unwrap()[0];
        let turned = p.step(Kernel::TransformPoints { pose: IDENTITY }, &[facing]).unwrap()[0];
        p.sink(moved).unwrap();
        p.sink(turned).unwrap();
        let transform = ChainRun::new(Some(gpu), &p);

        ScanCamera {
            gpu,
            camera: Camera { intrinsics, pose, ..Camera::default() },
            extrinsic: pose,
            learn,
            scan,
            icp,
            transform,
            settings,
            learnt: Vec::new(),
            background: None,
            model: None,
            pose: IDENTITY,
            increment: IDENTITY,
        }
    }

    /// Frame `frame`: learnt as background (the first ones, of the empty scene), or the
    /// segmented cloud, registered, moved into the model's frame: its valid points.
    pub fn frame(&mut self, frame: usize) -> Option<Points> {
        let scene =
            Scene { wall_distance: 4.0, wall_reflectivity: 0.8, object_reflectivity: 0.6, ..Scene::turned_box() };
        let scene = if frame < LEARNING_FRAMES { Scene { object: None, ..scene } } else { scene };
        let simulated = simulate(&scene, Motion::Still, &self.camera, frame);
        let Some((background_intensity, background_distance)) = &self.background else {
            let mut out = self.learn.run(&[simulated.raw, simulated.black]).unwrap();
            self.learnt.push((out.remove(0), out.remove(0)));
            if self.learnt.len() == LEARNING_FRAMES {
                let (intensities, distances): (Vec<Image>, Vec<Image>) =
                    std::mem::take(&mut self.learnt).into_iter().unzip();
                self.background = Some((background(&intensities), background(&distances)));
            }
            return None;
        };
        let rays = self.camera.intrinsics.rays();
        let sources = [simulated.raw, simulated.black, background_intensity.clone(), background_distance.clone(), rays];
        let mut cloud = self.scan.run(&sources).unwrap();
        let (points, normals) = (cloud.remove(0), cloud.remove(0));

        if let Some((model_points, model_normals)) = &self.model {
            let (settings, intrinsics, icp) = (self.settings, self.camera.intrinsics, &mut self.icp);
            let mut first = Some([points.clone(), normals.clone(), model_points.clone(), model_normals.clone()]);
            let registration = iterate(&settings, self.increment, |pose| {
                icp.set_kernel(0, reduce(&settings, intrinsics, pose)).unwrap();
                let out = match first.take() {
                    Some(sources) => icp.run(&sources),
                    None => icp.rerun(),
                };
                let out = out.map_err(RegistrationError::Pipeline)?;
                Ok(std::array::from_fn(|k| out[0].data[k] as f64))
            });
            match registration {
                Ok(registration) => {
                    self.increment = registration.pose;
                    self.pose = compose(&self.pose, &registration.pose);
                }
                Err(RegistrationError::TooFewPairs { .. } | RegistrationError::Degenerate) => {}
                Err(error) => panic!("{error}"),
            }
        }
        self.model = Some((points.clone(), normals.clone()));

        let pose = compose(&self.extrinsic, &self.pose);
        let mut rotation = pose;
        for row in 0..3 {
            rotation[4 * row + 3] = 0.0;
        }
        self.transform.set_kernel(0, Kernel::TransformPoints { pose }).unwrap();
        self.transform.set_kernel(1, Kernel::TransformPoints { pose: rotation }).unwrap();
        let out = self.transform.run(&[points, normals]).unwrap();
        Some(valid_points(&out[0], &out[1]))
    }
}

/// One ICP step's reduction at `pose`.
fn reduce(settings: &IcpSettings, intrinsics: Intrinsics, pose: &Pose) -> Kernel {
    Kernel::IcpReduce {
        pose: *pose,
        intrinsics,
        max_distance: settings.max_distance,
        min_cos: settings.max_angle_degrees.to_radians().cos(),
    }
}

/// The scan's three cameras at `width × height`.
pub fn cameras(gpu: &Gpu, width: usize, height: usize) -> Vec<ScanCamera<'_>> {
    CAMERAS.iter().map(|&c| ScanCamera::new(gpu, c, width, height)).collect()
}

/// The valid points the cameras give over `frames`, camera after camera each frame.
pub fn accumulate(cameras: &mut [ScanCamera], frames: std::ops::Range<usize>) -> Points {
    let (mut points, mut normals) = (Vec::new(), Vec::new());
    for frame in frames {
        for camera in cameras.iter_mut() {
            if let Some((p, n)) = camera.frame(frame) {
                points.extend(p);
                normals.extend(n);
            }
        }
    }
    (points, normals)
}

/// The scan's accumulated cloud after `frames` frames of `width × height` cameras.
pub fn scan(gpu: &Gpu, width: usize, height: usize, frames: usize) -> Points {
    accumulate(&mut cameras(gpu, width, height), 0..frames)
}
