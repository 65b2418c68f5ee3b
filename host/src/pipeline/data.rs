//! What flows between the stages of a pipeline: raw frames, depth images, masks, flow fields, point clouds,
//! poses, integration times and RGBA images (the interfaces of `ToF.*`), their images kept on the GPU as
//! buffers (or on the CPU without an adapter) until a stage or a sink reads them.

use std::sync::Arc;

use gudsl_runtime::{
    camera::Pose,
    executor::{BufferSlot, Executor},
    Image,
};

pub use gudsl_runtime::Tensor;

/// A raw PMD frame: channels A and B of the four phase images (8 planes, `A0 B0 … A3 B3`).
#[derive(Debug, Clone)]
pub struct RawFrame {
    pub raw: Tensor,
    /// The chip's black image (8 planes), when the source knows it.
    pub black: Option<Tensor>,
    /// A black image (8 planes) still to be taken off `raw`, clamped at 0: a black-image
    /// correction run inside the first kernel of each stage it feeds (`fusion.rs` gives such
    /// frames only to stages that take them).
    pub black_owed: Option<Tensor>,
    /// The true radial distance per pixel (the simulator's), metres; NaN where unknown.
    pub truth: Option<Arc<Image>>,
    /// Integration time per phase image, microseconds.
    pub integration_us: f32,
    /// When the frame was recorded (a bag's), ns since the epoch.
    pub stamp: Option<u64>,
}

/// A demodulated frame.
#[derive(Debug, Clone)]
pub struct DepthImage {
    /// Radial distance in metres, 0 where invalid.
    pub distance: Tensor,
    pub amplitude: Tensor,
    pub intensity: Tensor,
    pub truth: Option<Arc<Image>>,
    pub integration_us: f32,
    /// When the frame was recorded (a bag's), ns since the epoch.
    pub stamp: Option<u64>,
}

/// Points in the camera's frame (3 planes) and their normals (3 planes, zero until computed),
/// or an accumulated cloud of any number of points, in host memory.
#[derive(Debug, Clone)]
pub enum PointCloud {
    Organized { points: Tensor, normals: Tensor },
    Unorganized { points: Arc<Vec<[f32; 3]>>, normals: Arc<Vec<[f32; 3]>> },
}

/// An RGBA image of 8-bit values (`ToF.RgbaImage`): 4 planes R, G, B, A of values 0–255.
#[derive(Debug, Clone)]
pub struct Picture {
    pub texels: Tensor,
    /// The source instance it came from (a viewer names its files after it).
    pub source: String,
}

/// One item of data.
#[derive(Debug, Clone)]
pub enum Data {
    Raw(RawFrame),
    Depth(DepthImage),
    Mask(Tensor),
    /// Motion compensation's flow: 2 planes, dx and dy in pixels per phase image.
    Flow(Tensor),
    Cloud(PointCloud),
    Pose(Pose),
    IntegrationTime(f32),
    Image(Picture),
}

impl Data {
    /// What it is, with its size and element type, as a binding's label says it:
    /// `4×2×200×200 f32 raw`, `200×200 f32 depth`, `1 523 points`.
    pub fn describe(&self) -> String {
        let planes = |t: &Tensor, what: &str| {
            let s = t.shape();
            match s.planes {
                1 => format!("{}×{} {what}", s.width, s.height),
                n => format!("{n}×{}×{} {what}", s.width, s.height),
            }
        };
        match self {
            Data::Raw(frame) => {
                let s = frame.raw.shape();
                format!("4×2×{}×{} f32 raw", s.width, s.height)
            }
            Data::Depth(depth) => planes(&depth.distance, "f32 depth"),
            Data::Mask(mask) => planes(mask, "mask"),
            Data::Flow(flow) => planes(flow, "f32 flow"),
            Data::Cloud(PointCloud::Organized { points, .. }) => {
                let s = points.shape();
                format!("{}×{} points", s.width, s.height)
            }
            Data::Cloud(PointCloud::Unorganized { points, .. }) => format!("{} points", points.len()),
            Data::Pose(_) => "pose".to_string(),
            Data::IntegrationTime(_) => "integration time".to_string(),
            Data::Image(picture) => {
                let s = picture.texels.shape();
                format!("{}×{} RGBA8", s.width, s.height)
            }
        }
    }
}

/// An item delivered to a stage: its data, and the instance that produced it (a sink fed by
/// several names its outputs after their producers).
#[derive(Debug, Clone)]
pub struct Item {
    pub data: Data,
    pub producer: String,
    /// The frame it belongs to.
    pub frame: usize,
}

/// `data` with its GPU images copied into buffers of their own, so it outlives the frame (a
/// queued item: its producer writes its buffers again next frame).
pub fn detached(executor: &mut Executor, data: &Data) -> Data {
    let mut copy = |t: &Tensor| executor.keep(&mut BufferSlot::default(), t);
    match data {
        Data::Raw(frame) => {
            let black = frame.black.as_ref().map(&mut copy);
            let black_owed = frame.black_owed.as_ref().map(&mut copy);
            Data::Raw(RawFrame { raw: copy(&frame.raw), black, black_owed, ..frame.clone() })
        }
        Data::Depth(depth) => Data::Depth(DepthImage {
            distance: copy(&depth.distance),
            amplitude: copy(&depth.amplitude),
            intensity: copy(&depth.intensity),
            ..depth.clone()
        }),
        Data::Mask(mask) => Data::Mask(copy(mask)),
        Data::Flow(flow) => Data::Flow(copy(flow)),
        Data::Image(picture) => Data::Image(Picture { texels: copy(&picture.texels), source: picture.source.clone() }),
        Data::Cloud(PointCloud::Organized { points, normals }) => {
            Data::Cloud(PointCloud::Organized { points: copy(points), normals: copy(normals) })
        }
        other => other.clone(),
    }
}
