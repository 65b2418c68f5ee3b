//! The ToF library's components as code: what each `ToF.*` class of `model/lib/tof.gudsl` does
//! when a stage of its class runs, made from the stage's parameters (`make`). Sources
//! (`sources.rs`), filters on raw frames (`raw.rs`), on depth images (`depth.rs`), chapter 5's
//! integration time (`exposure.rs`), chapter 6's segmentation, clouds and registration
//! (`cloud.rs`), RGBA images (`images.rs`), sinks (`sinks.rs`, ROS 2 bags `bags.rs`); and the workspace's own
//! components, whose `process` runs device diagrams (`workspace.rs`).

mod accuracy;
mod bags;
mod cloud;
mod depth;
mod exposure;
mod images;
mod per_frame;
mod ports;
mod raw;
mod sinks;
mod sources;
mod texels;
mod workspace;

pub use per_frame::PerFrame;
pub use workspace::{behaviors, Behaviors};

use std::{collections::BTreeMap, sync::atomic::AtomicBool};

use gudsl_model::hir::pipeline::{Stage, Value};

use super::{
    data::{Data, DepthImage, Item},
    executor::{Executor, Reads},
    ErrorKind, OutputDir, PipelineError,
};
use crate::access::ModelFiles;

/// What a component sees while it runs.
pub struct Ctx<'a, 'g> {
    pub device: &'a mut Executor<'g>,
    /// The stage's index in the plan (its kernels are timed under it).
    pub stage: usize,
    pub frame: usize,
    pub output: &'a mut OutputDir,
    /// Set when the run is cancelled: long work inside a frame asks it (the simulator, a row at
    /// a time).
    pub cancel: &'a AtomicBool,
}

/// The items that arrived on a stage's processor ports this frame, by port.
#[derive(Default)]
pub struct Inputs(BTreeMap<String, Vec<Item>>);

impl Inputs {
    pub fn push(&mut self, port: &str, item: Item) {
        self.0.entry(port.to_string()).or_default().push(item);
    }

    pub fn is_empty(&self) -> bool {
        self.0.values().all(Vec::is_empty)
    }

    pub fn len(&self) -> usize {
        self.0.values().map(Vec::len).sum()
    }

    /// Every item, port by port.
    pub fn all(&self) -> impl Iterator<Item = &Item> {
        self.0.values().flatten()
    }

    /// The ports and their items.
    pub fn by_port(&self) -> impl Iterator<Item = (&str, &[Item])> {
        self.0.iter().map(|(port, items)| (port.as_str(), items.as_slice()))
    }

    /// The items of `port`, in the order they arrived.
    pub fn port(&self, port: &str) -> &[Item] {
        self.0.get(port).map_or(&[], Vec::as_slice)
    }
}

/// The depth images that arrived on `DepthIn`, with their producers.
pub fn depth_images(inputs: &Inputs) -> impl Iterator<Item = (&str, &DepthImage)> {
    inputs.port("DepthIn").iter().filter_map(|item| match &item.data {
        Data::Depth(depth) => Some((item.producer.as_str(), depth)),
        _ => None,
    })
}

/// The planes of a depth image a writer was asked for (`distance`, `amplitude`, `intensity`),
/// each with its name.
pub fn depth_planes<'d>(
    depth: &'d DepthImage,
    planes: &'d [&'static str],
) -> impl Iterator<Item = (&'static str, &'d super::data::Tensor)> + 'd {
    planes.iter().map(move |&what| {
        let tensor = match what {
            "distance" => &depth.distance,
            "amplitude" => &depth.amplitude,
            _ => &depth.intensity,
        };
        (what, tensor)
    })
}

/// Channel A (`first` 0) or B (1) of a raw frame (planes `A0 B0 A1 B1 …`): its four phase
/// images one after the other, as a recording holds them.
pub fn channel(raw: &gudsl_runtime::Image, first: usize) -> Vec<f32> {
    (0..4).flat_map(|k| raw.plane(2 * k + first).iter().copied()).collect()
}

/// The slots of the `k`-th item of a frame (each item its own buffers: a later item must not
/// overwrite an earlier one's results before they are read).
pub fn slots<T: Default>(slots: &mut Vec<T>, k: usize) -> &mut T {
    if slots.len() <= k {
        slots.resize_with(k + 1, T::default);
    }
    &mut slots[k]
}

/// An image's width and height.
pub type Size = (usize, usize);

/// The sizes of the images that can arrive on each of a stage's ports.
pub type SizesByPort = BTreeMap<String, std::collections::BTreeSet<Size>>;

/// `width×height`.
pub fn size_text((width, height): Size) -> String {
    format!("{width}×{height}")
}

/// Whether every image arriving on `port` (`given`: what they are, "frames") is `own` in size;
/// if not, the error at `param`: "`what` is W×H, the `given` it is given W×H: `advice`".
pub fn of_size(
    sizes: &SizesByPort,
    (port, given): (&str, &str),
    own: Size,
    param: &'static str,
    what: &str,
    advice: &str,
) -> Result<(), (Option<&'static str>, String)> {
    match sizes.get(port).into_iter().flatten().find(|&&size| size != own) {
        Some(&other) => Err((
            Some(param),
            format!("{what} is {}, the {given} it is given {}: {advice}", size_text(own), size_text(other)),
        )),
        None => Ok(()),
    }
}

/// What the items a stage gives carry beside their images, known before a run (`carries.rs`
/// follows it down the bindings): raw frames a black image of their own, frames and depth
/// images the scene's true distances (a simulated camera's do, a recording's do not), point
/// clouds the camera's grid (an accumulated cloud has none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Carries {
    pub black: bool,
    pub truth: bool,
    pub organized: bool,
}

impl Carries {
    /// What every item can carry: where nothing has arrived yet.
    pub const ALL: Carries = Carries { black: true, truth: true, organized: true };

    /// What items from both carry.
    pub fn and(self, other: Carries) -> Carries {
        Carries {
            black: self.black && other.black,
            truth: self.truth && other.truth,
            organized: self.organized && other.organized,
        }
    }
}

/// What a component needs the items it is given to carry, and what to do where they do not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// A black image of the frame's own; the advice.
    Black(&'static str),
    /// The true distances; the advice.
    Truth(&'static str),
    /// Clouds on a camera's grid; the advice.
    Organized(&'static str),
}

/// What a stage produced: data for its provider ports, by port name.
pub type Outputs = Vec<(String, Data)>;

/// A running component (made where the plan is read, run on the thread that runs the pipeline).
pub trait Component: Send {
    /// The frames a source gives (`None`: not a source).
    fn frames(&self) -> Option<usize> {
        None
    }

    /// The size (width, height) of the images a source gives.
    fn image_size(&self) -> Option<Size> {
        None
    }

    /// Whether images of these sizes, by port (what each binding into it can carry), can meet
    /// in it; else the parameter concerned (if one) and what does not fit.
    fn sizes_meet(&self, _sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        Ok(())
    }

    /// What the items it gives carry, given what the items it is given carry: a filter passes
    /// on what arrives, a source says what its own carry.
    fn carries(&self, arriving: Carries) -> Carries {
        arriving
    }

    /// What the items it is given must carry for it to run.
    fn needs(&self) -> Option<Need> {
        None
    }

    /// A setting that cannot act in a run of `frames` frames: the parameter and why.
    fn cannot_act(&self, _frames: usize) -> Option<(&'static str, String)> {
        None
    }

    /// A file of it that holds too little for a run of `frames` frames: the parameter and why
    /// (E0404 before the run, not an error at the frame that finds it missing).
    fn too_short(&self, _frames: usize) -> Option<(&'static str, String)> {
        None
    }

    /// Before the first frame: reads what it needs from files (their headers were checked when
    /// it was made). `Err` is a message naming the file.
    fn load(&mut self) -> Result<(), String> {
        Ok(())
    }

    /// One frame: the items that arrived (none for a source) in, data for the provider ports
    /// out. `Err` is a message for the user.
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String>;

    /// After the frame's reads came back (what [`Executor::read_later`] asked for): what
    /// needs the data on the host (sinks write files); anything it gives arrives next frame.
    fn finish_frame(&mut self, _ctx: &mut Ctx, _reads: &Reads) -> Result<Outputs, String> {
        Ok(Vec::new())
    }

    /// Whether the next frame's `process` needs what `finish_frame` learns from this frame's
    /// reads (its state, or what it gives): then a pipeline's frames run one after another.
    /// Else the next frame is recorded while the GPU works on this one, and what the
    /// component keeps for a frame's `finish_frame` is kept by frame ([`PerFrame`]).
    fn feeds_back(&self) -> bool {
        false
    }

    /// Whether it takes raw frames that still owe their black image ([`RawFrame::black_owed`]),
    /// taking it off in its own first kernel (then a black-image correction feeding only such
    /// stages runs inside them: `fusion.rs`).
    ///
    /// [`RawFrame::black_owed`]: super::data::RawFrame::black_owed
    fn takes_owed_black(&self) -> bool {
        false
    }

    /// Told (`owe`) that each stage it feeds takes frames owing their black image: whether it
    /// then gives them so instead of taking the black image off itself (a black-image
    /// correction does; nothing else subtracts one).
    fn owe_black(&mut self, _owe: bool) -> bool {
        false
    }

    /// After the last frame (a plot, a last cloud).
    fn finish_run(&mut self, _output: &mut OutputDir) -> Result<(), String> {
        Ok(())
    }

    /// What it measured over the run, by name (a series' mean error in cm): a row of a
    /// parameter study's table.
    fn figures(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
}

/// The component of a stage's class with its parameters, or why there is none: a class of the
/// ToF library, or a class of the workspace that extends one or whose `process` runs device
/// diagrams (`behaviors`: their kernels).
pub fn make(
    stage: &Stage,
    providers: usize,
    files: &ModelFiles,
    behaviors: &Behaviors,
) -> Result<Box<dyn Component>, Vec<PipelineError>> {
    let params = Params { stage, providers, files };
    if let Some(made) = library(&stage.class, &params) {
        return made.map(|component| ports::on_stage_ports(component, stage));
    }
    let base = stage.bases.iter().find_map(|base| library(base, &params)).transpose()?;
    if stage.class.starts_with("ToF.") && base.is_none() {
        let message = "this component of the ToF library cannot run yet".to_string();
        return Err(vec![params.stage_error(ErrorKind::NotRunnable, message)]);
    }
    workspace::make(&params, base, behaviors)
}

/// The library component `class` made from `params`, `None` if `class` is none.
fn library(class: &str, params: &Params) -> Option<Result<Box<dyn Component>, Vec<PipelineError>>> {
    fn made(component: impl Component + 'static) -> Result<Box<dyn Component>, Vec<PipelineError>> {
        Ok(Box::new(component))
    }
    Some(match class {
        "ToF.SimulatedCamera" => made(sources::Simulated::new(params, false)),
        "ToF.ControlledCamera" => made(sources::Simulated::new(params, true)),
        "ToF.AmplitudeCamera" => made(images::AmplitudeCamera::new(params)),
        "ToF.RawFrameFile" => sources::RawFrameFile::new(params).and_then(made),
        "ToF.DepthFile" => sources::DepthFile::new(params).and_then(made),
        "ToF.BlackImageCorrection" => raw::BlackImageCorrection::new(params).and_then(made),
        "ToF.Demodulation" => made(raw::Demodulation::new(params)),
        "ToF.MotionCompensation" => raw::MotionCompensation::new(params).and_then(made),
        "ToF.IntegrationTimeControl" => exposure::IntegrationTimeControl::new(params).and_then(made),
        "ToF.IntensityCorrection"
        | "ToF.AmplitudeMask"
        | "ToF.MedianFilter"
        | "ToF.GaussianFilter"
        | "ToF.BilateralFilter"
        | "ToF.OutlierRemoval" => made(depth::DepthKernel::new(params)),
        "ToF.AmplitudeImage" => made(images::AmplitudeImage::new(params)),
        "ToF.BackgroundSegmentation" => made(cloud::BackgroundSegmentation::new(params)),
        "ToF.ApplyMask" => made(cloud::ApplyMask::default()),
        "ToF.PointCloudConversion" => made(cloud::PointCloudConversion::default()),
        "ToF.IcpRegistration" => made(cloud::IcpRegistration::new(params)),
        "ToF.CloudTransform" => made(cloud::CloudTransform::new(params)),
        "ToF.Accumulation" => made(cloud::Accumulation::default()),
        "ToF.NpyWriter" => made(sinks::DepthWriter::new(params, sinks::DepthFormat::Npy)),
        "ToF.ExrWriter" => made(sinks::DepthWriter::new(params, sinks::DepthFormat::Exr)),
        "ToF.McapWriter" => made(bags::McapWriter::new(params)),
        "ToF.PlyWriter" => made(sinks::CloudWriter::new(params, sinks::CloudFormat::Ply)),
        "ToF.PcdWriter" => made(sinks::CloudWriter::new(params, sinks::CloudFormat::Pcd)),
        "ToF.CloudFile" => sources::CloudFile::new(params).and_then(made),
        "ToF.PngWriter" => made(sinks::PngWriter::new(params)),
        "ToF.MaskWriter" => made(sinks::MaskWriter::new(params)),
        "ToF.RawWriter" => made(sinks::RawWriter::new(params)),
        "ToF.FlowWriter" => made(sinks::FlowWriter::new(params)),
        "ToF.ImageViewer" => made(images::ImageViewer::new(params)),
        "ToF.AccuracyReport" => accuracy::AccuracyReport::new(params).and_then(made),
        _ => return None,
    })
}

/// A stage's parameters as the types its component reads them in. The plan checked their
/// ranges; a field without a value reads as its type's zero (C++'s default).
pub struct Params<'a> {
    pub stage: &'a Stage,
    /// How many bindings feed the stage.
    pub providers: usize,
    pub files: &'a ModelFiles,
}

impl Params<'_> {
    pub fn number(&self, name: &str) -> f64 {
        self.stage.param(name).and_then(Value::number).unwrap_or(0.0)
    }

    pub fn f32(&self, name: &str) -> f32 {
        self.number(name) as f32
    }

    pub fn count(&self, name: &str) -> usize {
        self.number(name).max(0.0) as usize
    }

    pub fn flag(&self, name: &str) -> bool {
        matches!(self.stage.param(name), Some(Value::Bool(true)))
    }

    /// An enum parameter's member name.
    pub fn member(&self, name: &str) -> &str {
        match self.stage.param(name) {
            Some(Value::Enum(member)) => member,
            _ => "",
        }
    }

    /// A text parameter's value ("" when not text).
    pub fn text(&self, name: &str) -> &str {
        match self.stage.param(name) {
            Some(Value::Text(text)) => text,
            _ => "",
        }
    }

    /// A file parameter as a path (relative to the model's folder; `archive.npz:name` names an
    /// array of an archive), `None` when empty.
    pub fn file(&self, name: &str) -> Option<std::path::PathBuf> {
        match self.stage.param(name) {
            Some(Value::Text(text)) if !text.is_empty() => Some(self.files.path(text)),
            _ => None,
        }
    }

    /// A file parameter the component cannot do without.
    pub fn required_file(&self, name: &str) -> Result<std::path::PathBuf, Vec<PipelineError>> {
        self.file(name).ok_or_else(|| {
            vec![self.error(name, ErrorKind::Input, format!("`{name}` names no file: give the file to read"))]
        })
    }

    /// An error about parameter `name`, at its value (or at the instance).
    pub fn error(&self, name: &str, kind: ErrorKind, message: String) -> PipelineError {
        let range =
            self.stage.params.iter().find(|p| p.name == name).and_then(|p| p.written).unwrap_or(self.stage.range);
        PipelineError { range: Some(range), ..self.stage_error(kind, message) }
    }

    /// An error about the stage as a whole, at the instance's name.
    pub fn stage_error(&self, kind: ErrorKind, message: String) -> PipelineError {
        PipelineError { kind, stage: Some(self.stage.instance.clone()), range: Some(self.stage.range), message }
    }
}
