//! Chapter 6's chain after the depth filters: the background learnt from the first frames and
//! the foreground segmented against it (sec. 6.5.2), masks applied, depth images turned into
//! point clouds with normals, clouds registered frame to frame by projective point-to-plane ICP
//! (sec. 6.5.3, its sums reduced where the clouds are and read back each iteration), moved into
//! the model's frame, and accumulated into one cloud (sec. 6.5.4.2).

use std::{collections::HashMap, sync::Arc};

use gudsl_formats::ply::Points;
use gudsl_runtime::{
    camera::{apply, compose, pose_from, Intrinsics, Pose, IDENTITY},
    kernels::car::background,
    registration::{iterate, valid_points, IcpSettings, RegistrationError},
    Image, Kernel, Shape,
};

use super::{
    depth_images, size_text, slots, Carries, Component, Ctx, Inputs, Need, Outputs, Params, Size, SizesByPort,
};
use crate::pipeline::{
    data::{Data, DepthImage, PointCloud, Tensor},
    executor::{BufferSlot, KernelSlot, Later, Reads},
};

/// The organized clouds that arrived on `CloudIn`, with their producers.
fn clouds(inputs: &Inputs) -> impl Iterator<Item = (&str, &PointCloud)> {
    inputs.port("CloudIn").iter().filter_map(|item| match &item.data {
        Data::Cloud(cloud) => Some((item.producer.as_str(), cloud)),
        _ => None,
    })
}

/// A kernel's results on the device, or the message of why it could not run.
fn run(ctx: &mut Ctx, slot: &mut KernelSlot, kernel: Kernel, inputs: &[&Tensor]) -> Result<Vec<Tensor>, String> {
    ctx.device.kernel(ctx.stage, slot, kernel, inputs).map_err(|e| e.to_string())
}

/// `ToF.BackgroundSegmentation`: the first `learningFrames` depth images of each producer (of
/// the empty scene) are its background — per pixel the median intensity and distance —, every
/// later one gives the mask of what differs from it by more than either threshold, opened and
/// closed.
pub struct BackgroundSegmentation {
    learning_frames: usize,
    theta_intensity: f32,
    theta_distance: f32,
    radius: u32,
    /// Each producer's background, learnt from its own images.
    models: HashMap<String, Background>,
    kernels: Vec<[KernelSlot; 5]>,
}

/// One producer's background, being learnt or learnt.
#[derive(Default)]
struct Background {
    /// The learning frames' intensity and distance as they are read back.
    learnt: Vec<(Image, Image)>,
    pending: Vec<(Later, Later)>,
    learnt_on_device: Option<(Tensor, Tensor)>,
    slots: [BufferSlot; 2],
}

impl BackgroundSegmentation {
    pub fn new(params: &Params) -> BackgroundSegmentation {
        BackgroundSegmentation {
            learning_frames: params.count("learningFrames").max(1),
            theta_intensity: params.f32("intensityThreshold"),
            theta_distance: params.f32("distanceThreshold"),
            radius: params.count("morphologyRadius") as u32,
            models: HashMap::new(),
            kernels: Vec::new(),
        }
    }
}

impl Component for BackgroundSegmentation {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, (producer, depth)) in depth_images(inputs).enumerate() {
            let model = self.models.entry(producer.to_string()).or_default();
            let Some((intensity, distance)) = &model.learnt_on_device else {
                if model.learnt.len() + model.pending.len() < self.learning_frames {
                    let reads = (ctx.device.read_later(&depth.intensity), ctx.device.read_later(&depth.distance));
                    model.pending.push(reads);
                }
                continue;
            };
            let [segment, erode, dilate, close_dilate, close_erode] = slots(&mut self.kernels, k);
            let kernel = Kernel::Segment { theta_intensity: self.theta_intensity, theta_distance: self.theta_distance };
            let mut mask =
                run(ctx, segment, kernel, &[&depth.intensity, &depth.distance, intensity, distance])?.remove(0);
            if self.radius > 0 {
                let r = self.radius;
                // Opening takes single pixels, closing fills holes.
                for (slot, dilate) in [(erode, false), (dilate, true), (close_dilate, true), (close_erode, false)] {
                    mask = run(ctx, slot, Kernel::Morphology { radius: r, dilate }, &[&mask])?.remove(0);
                }
            }
            out.push(("MaskOut".to_string(), Data::Mask(mask)));
        }
        Ok(out)
    }

    /// The background learnt from the first frames' reads segments the frames after them.
    fn feeds_back(&self) -> bool {
        true
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, model) in &mut self.models {
            for (intensity, distance) in std::mem::take(&mut model.pending) {
                model.learnt.push(((**reads.get(intensity)).clone(), (**reads.get(distance)).clone()));
            }
            if model.learnt_on_device.is_some() || model.learnt.len() < self.learning_frames {
                continue;
            }
            let size = |image: &Image| (image.width, image.height);
            if model.learnt.iter().any(|(i, _)| size(i) != size(&model.learnt[0].0)) {
                return Err(format!("the images from `{producer}` change size while the background is learnt"));
            }
            let (intensities, distances): (Vec<Image>, Vec<Image>) =
                std::mem::take(&mut model.learnt).into_iter().unzip();
            let [i, d] = &mut model.slots;
            model.learnt_on_device =
                Some((ctx.device.upload(i, &background(&intensities)), ctx.device.upload(d, &background(&distances))));
        }
        Ok(Vec::new())
    }
}

/// `ToF.ApplyMask`: each depth image's distance where the mask that arrived with it is set, 0
/// elsewhere; a depth image without a mask (while the background is learnt) goes nowhere.
#[derive(Default)]
pub struct ApplyMask {
    kernels: Vec<KernelSlot>,
}

impl Component for ApplyMask {
    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let of = |port: &str| sizes.get(port).cloned().unwrap_or_default();
        let (depth, masks) = (of("DepthIn"), of("MaskIn"));
        let text =
            |set: &std::collections::BTreeSet<Size>| set.iter().map(|&s| size_text(s)).collect::<Vec<_>>().join(", ");
        if !depth.is_empty() && !masks.is_empty() && depth != masks {
            return Err((
                None,
                format!("it is given depth images of {} and masks of {}: they cannot meet", text(&depth), text(&masks)),
            ));
        }
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let masks = inputs.port("MaskIn").iter().filter_map(|item| match &item.data {
            Data::Mask(mask) => Some(mask),
            _ => None,
        });
        let mut out = Vec::new();
        for (k, ((_, depth), mask)) in depth_images(inputs).zip(masks).enumerate() {
            let distance =
                run(ctx, slots(&mut self.kernels, k), Kernel::ApplyMask, &[&depth.distance, mask])?.remove(0);
            out.push(("DepthOut".to_string(), Data::Depth(DepthImage { distance, ..depth.clone() })));
        }
        Ok(out)
    }
}

/// `ToF.PointCloudConversion`: each distance along its pixel's ray (Table 2.1's camera at the
/// image's size, as the simulated camera has it), normals by central differences.
#[derive(Default)]
pub struct PointCloudConversion {
    /// The rays of each image size met.
    rays: HashMap<(usize, usize), (BufferSlot, Option<Tensor>)>,
    kernels: Vec<[KernelSlot; 2]>,
}

impl Component for PointCloudConversion {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, (_, depth)) in depth_images(inputs).enumerate() {
            let Shape { width, height, .. } = depth.distance.shape();
            let (slot, rays) = self.rays.entry((width, height)).or_default();
            let rays = rays
                .get_or_insert_with(|| ctx.device.upload(slot, &Intrinsics::camcube_at(width, height).rays()))
                .clone();
            let [to_points, to_normals] = slots(&mut self.kernels, k);
            let points = run(ctx, to_points, Kernel::PointCloud, &[&depth.distance, &rays])?.remove(0);
            let normals = run(ctx, to_normals, Kernel::Normals, &[&points])?.remove(0);
            out.push(("CloudOut".to_string(), Data::Cloud(PointCloud::Organized { points, normals })));
        }
        Ok(out)
    }
}

/// `ToF.IcpRegistration`: each organized cloud registered against the one before from the same
/// producer (the previous increment as the guess), the increments chained into the pose of the
/// current cloud in the first one's frame; identity for the first. A frame it cannot register
/// (too few pairs: its mask nearly empty; a degenerate system) keeps the last pose.
pub struct IcpRegistration {
    settings: IcpSettings,
    /// Per producer: the previous cloud (points, normals), its pose, the last increment.
    tracks: HashMap<String, Track>,
}

struct Track {
    model: [BufferSlot; 2],
    kept: Option<(Tensor, Tensor)>,
    pose: Pose,
    increment: Pose,
    reduce: KernelSlot,
}

impl IcpRegistration {
    pub fn new(params: &Params) -> IcpRegistration {
        let settings = IcpSettings {
            max_distance: params.f32("maxDistance"),
            max_angle_degrees: params.f32("maxAngle"),
            max_iterations: params.count("maxIterations").max(1),
            ..IcpSettings::default()
        };
        IcpRegistration { settings, tracks: HashMap::new() }
    }
}

impl Component for IcpRegistration {
    fn needs(&self) -> Option<Need> {
        Some(Need::Organized("ICP registers a camera's clouds (from a PointCloudConversion)"))
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (producer, cloud) in clouds(inputs) {
            let PointCloud::Organized { points, normals } = cloud else {
                return Err(format!("`{producer}` gives an accumulated cloud: ICP registers a camera's clouds"));
            };
            let track = self.tracks.entry(producer.to_string()).or_insert_with(|| Track {
                model: Default::default(),
                kept: None,
                pose: IDENTITY,
                increment: IDENTITY,
                reduce: KernelSlot::default(),
            });
            if let Some((model_points, model_normals)) = &track.kept {
                let Shape { width, height, .. } = points.shape();
                let intrinsics = Intrinsics::camcube_at(width, height);
                let settings = self.settings;
                let min_cos = settings.max_angle_degrees.to_radians().cos();
                let registration = iterate(&settings, track.increment, |pose| {
                    let kernel =
                        Kernel::IcpReduce { pose: *pose, intrinsics, max_distance: settings.max_distance, min_cos };
                    let inputs = [points, normals, model_points, model_normals];
                    let sums = ctx.device.kernel(ctx.stage, &mut track.reduce, kernel, &inputs);
                    let sums = sums.map_err(RegistrationError::Pipeline)?.remove(0);
                    let read = ctx.device.read_now(&[&sums]).map_err(RegistrationError::Pipeline)?;
                    Ok(std::array::from_fn(|k| read[0].data[k] as f64))
                });
                match registration {
                    Ok(registration) => {
                        track.increment = registration.pose;
                        track.pose = compose(&track.pose, &registration.pose);
                    }
                    // Too few pairs or a degenerate system (a frame whose mask is nearly
                    // empty): the frame keeps the last pose, and the next registers against it.
                    Err(RegistrationError::TooFewPairs { .. } | RegistrationError::Degenerate) => {}
                    Err(error) => return Err(format!("frame {} of `{producer}`: {error}", ctx.frame)),
                }
            }
            let [p, n] = &mut track.model;
            track.kept = Some((ctx.device.keep(p, points), ctx.device.keep(n, normals)));
            out.push(("PoseOut".to_string(), Data::Pose(track.pose)));
        }
        Ok(out)
    }
}

/// `ToF.CloudTransform`: clouds moved by the pose last received (a registration's: the cloud in
/// its camera's first frame), then by the extrinsic pose (that camera in the model's frame).
pub struct CloudTransform {
    extrinsic: Pose,
    received: Pose,
    kernels: Vec<[KernelSlot; 2]>,
}

impl CloudTransform {
    pub fn new(params: &Params) -> CloudTransform {
        let degrees = |name: &str| params.number(name).to_radians();
        let extrinsic = pose_from(
            [degrees("pitch"), degrees("yaw"), degrees("roll")],
            [params.number("x"), params.number("y"), params.number("z")],
        );
        CloudTransform { extrinsic, received: IDENTITY, kernels: Vec::new() }
    }
}

impl Component for CloudTransform {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        if let Some(Data::Pose(pose)) = inputs.port("PoseIn").last().map(|item| &item.data) {
            self.received = *pose;
        }
        let pose = compose(&self.extrinsic, &self.received);
        let mut rotation = pose;
        for row in 0..3 {
            rotation[4 * row + 3] = 0.0;
        }
        let mut out = Vec::new();
        for (k, (_, cloud)) in clouds(inputs).enumerate() {
            let moved = match cloud {
                PointCloud::Organized { points, normals } => {
                    let [to_points, to_normals] = slots(&mut self.kernels, k);
                    let points = run(ctx, to_points, Kernel::TransformPoints { pose }, &[points])?.remove(0);
                    let normals =
                        run(ctx, to_normals, Kernel::TransformPoints { pose: rotation }, &[normals])?.remove(0);
                    PointCloud::Organized { points, normals }
                }
                PointCloud::Unorganized { points, normals } => PointCloud::Unorganized {
                    points: Arc::new(points.iter().map(|p| apply(&pose, *p, true)).collect()),
                    normals: Arc::new(normals.iter().map(|n| apply(&pose, *n, false)).collect()),
                },
            };
            out.push(("CloudOut".to_string(), Data::Cloud(moved)));
        }
        Ok(out)
    }
}

/// `ToF.Accumulation`: every valid point (z ≠ 0) of every cloud it receives, in one cloud given
/// each frame.
#[derive(Default)]
pub struct Accumulation {
    points: Arc<Vec<[f32; 3]>>,
    normals: Arc<Vec<[f32; 3]>>,
}

impl Component for Accumulation {
    /// One cloud of all it was given: no camera's grid.
    fn carries(&self, arriving: Carries) -> Carries {
        Carries { organized: false, ..arriving }
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let given: Vec<&PointCloud> = clouds(inputs).map(|(_, cloud)| cloud).collect();
        for (points, normals) in host_clouds(ctx, &given)? {
            Arc::make_mut(&mut self.points).extend(points);
            Arc::make_mut(&mut self.normals).extend(normals);
        }
        let cloud = PointCloud::Unorganized { points: self.points.clone(), normals: self.normals.clone() };
        Ok(vec![("CloudOut".to_string(), Data::Cloud(cloud))])
    }
}

/// Clouds' valid points and normals in host memory, the organized ones read back now, all in
/// one read (one submission, whatever the number of cameras).
pub fn host_clouds(ctx: &mut Ctx, clouds: &[&PointCloud]) -> Result<Vec<Points>, String> {
    let organized: Vec<&Tensor> = clouds
        .iter()
        .filter_map(|cloud| match cloud {
            PointCloud::Organized { points, normals } => Some([points, normals]),
            PointCloud::Unorganized { .. } => None,
        })
        .flatten()
        .collect();
    let read =
        if organized.is_empty() { Vec::new() } else { ctx.device.read_now(&organized).map_err(|e| e.to_string())? };
    let mut read = read.chunks(2);
    Ok(clouds
        .iter()
        .map(|cloud| match cloud {
            PointCloud::Unorganized { points, normals } => (points.to_vec(), normals.to_vec()),
            PointCloud::Organized { .. } => {
                let pair = read.next().expect("read above");
                valid_points(&pair[0], &pair[1])
            }
        })
        .collect())
}

/// A cloud as a sink asks for it in `process`: in host memory already, or its points and
/// normals read at the end of the frame (no submission of its own).
pub enum CloudRead {
    Known(Points),
    Later(Later, Later),
}

impl CloudRead {
    pub fn ask(ctx: &mut Ctx, cloud: &PointCloud) -> CloudRead {
        match cloud {
            PointCloud::Unorganized { points, normals } => CloudRead::Known((points.to_vec(), normals.to_vec())),
            PointCloud::Organized { points, normals } => {
                CloudRead::Later(ctx.device.read_later(points), ctx.device.read_later(normals))
            }
        }
    }

    /// Its valid points and normals, once the frame's reads are back.
    pub fn take(self, reads: &Reads) -> Points {
        match self {
            CloudRead::Known(points) => points,
            CloudRead::Later(points, normals) => valid_points(reads.get(points), reads.get(normals)),
        }
    }
}
