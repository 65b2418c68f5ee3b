//! Filters on raw frames: the black image subtracted (chapter 2.1, Sec. 6.5.1.2), motion
//! artifacts compensated (chapter 4), and the demodulation into depth images (Sec. 2.1.1).

use std::path::Path;

use gudsl_runtime::{phase_normalization::PhaseCalibration, Image, Kernel};

use super::{of_size, slots, Carries, Component, Ctx, Inputs, Need, Outputs, Params, SizesByPort};
use crate::pipeline::{
    data::{Data, DepthImage, RawFrame, Tensor},
    executor::{BufferSlot, KernelSlot},
    files::{self, RawFiles},
    ErrorKind, PipelineError,
};

/// The raw frames that arrived on `RawIn`, with their index among this frame's items.
fn raw_frames(inputs: &Inputs) -> impl Iterator<Item = (usize, &RawFrame)> {
    inputs
        .port("RawIn")
        .iter()
        .filter_map(|item| match &item.data {
            Data::Raw(frame) => Some(frame),
            _ => None,
        })
        .enumerate()
}

/// Where a frame owing its black image reached a stage that does not take one (`fusion.rs`
/// gives such frames only to stages that do: never expected).
const OWED: &str = "internal error: a frame still owing its black image reached a stage that reads it as it is";

/// `ToF.BlackImageCorrection`: raw − black, the black image the frame's own or read from files.
pub struct BlackImageCorrection {
    /// The black image's files, if given.
    files: Option<RawFiles>,
    /// The black image from files (8 planes), once loaded.
    black: Option<Image>,
    uploaded: BufferSlot,
    kernels: Vec<KernelSlot>,
    /// Whether its frames owe the black image to the stages it feeds, which take it off in
    /// their own first kernels (`fusion.rs`), instead of its kernel taking it off.
    owes: bool,
}

impl BlackImageCorrection {
    pub fn new(params: &Params) -> Result<BlackImageCorrection, Vec<PipelineError>> {
        let files = match (params.file("channelA"), params.file("channelB")) {
            (None, None) => None,
            (Some(a), Some(b)) => Some(open_raw_files(params, &a, &b)?),
            (Some(_), None) => {
                return Err(vec![params.error("channelA", ErrorKind::Input, "give channelB too".into())])
            }
            (None, Some(_)) => {
                return Err(vec![params.error("channelB", ErrorKind::Input, "give channelA too".into())])
            }
        };
        if let Some(files) = &files {
            if files.extent.frames != 1 {
                let message =
                    format!("a black image is one frame, shape (4, H, W); the files hold {}", files.extent.frames);
                return Err(vec![params.error("channelA", ErrorKind::Input, message)]);
            }
        }
        Ok(BlackImageCorrection {
            files,
            black: None,
            uploaded: BufferSlot::default(),
            kernels: Vec::new(),
            owes: false,
        })
    }
}

/// A recording's channel files (`channelA`, `channelB`), each problem at its parameter.
pub fn open_raw_files(params: &Params, a: &Path, b: &Path) -> Result<RawFiles, Vec<PipelineError>> {
    RawFiles::open(params.files, a, b).map_err(|errors| {
        let at = |e: &files::FileError| if e.in_b { "channelB" } else { "channelA" };
        errors.into_iter().map(|e| params.error(at(&e), ErrorKind::Input, e.message)).collect()
    })
}

impl Component for BlackImageCorrection {
    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let Some(files) = &self.files else { return Ok(()) };
        let own = (files.extent.width, files.extent.height);
        of_size(sizes, ("RawIn", "frames"), own, "channelA", "the black image", "they cannot meet")
    }

    /// Its frames have had their black image subtracted: they carry none any more.
    fn carries(&self, arriving: Carries) -> Carries {
        Carries { black: false, ..arriving }
    }

    /// Without files of its own, each frame's own black image.
    fn needs(&self) -> Option<Need> {
        self.files.is_none().then_some(Need::Black("give the black image's files (channelA, channelB)"))
    }

    fn owe_black(&mut self, owe: bool) -> bool {
        self.owes = owe;
        owe
    }

    fn load(&mut self) -> Result<(), String> {
        if let Some(files) = &self.files {
            self.black = Some(files.frames(1).next_frame()?);
        }
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, frame) in raw_frames(inputs) {
            let black =
                match (&self.black, &frame.black) {
                    (Some(image), _) => ctx.device.upload(&mut self.uploaded, image),
                    (None, Some(black)) => black.clone(),
                    (None, None) => return Err(
                        "the frame has no black image of its own: give the black image's files (channelA, channelB)"
                            .into(),
                    ),
                };
            if frame.black_owed.is_some() {
                return Err(OWED.into());
            }
            let corrected = match self.owes {
                true => RawFrame { black: None, black_owed: Some(black), ..frame.clone() },
                false => {
                    let raw = ctx
                        .device
                        .kernel(ctx.stage, slots(&mut self.kernels, k), Kernel::SubtractBlack, &[&frame.raw, &black])
                        .map_err(|e| e.to_string())?
                        .remove(0);
                    RawFrame { raw, black: None, ..frame.clone() }
                }
            };
            out.push(("RawOut".to_string(), Data::Raw(corrected)));
        }
        Ok(out)
    }
}

/// `ToF.Demodulation`: raw frame → distance, amplitude, intensity.
pub struct Demodulation {
    modulation_hz: f32,
    kernels: Vec<KernelSlot>,
}

impl Demodulation {
    pub fn new(params: &Params) -> Demodulation {
        Demodulation { modulation_hz: params.f32("modulationFrequency") * 1e6, kernels: Vec::new() }
    }
}

impl Component for Demodulation {
    /// It takes the black image off in its own pass (`Kernel::SubtractBlackDemodulate`).
    fn takes_owed_black(&self) -> bool {
        true
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, frame) in raw_frames(inputs) {
            let modulation_hz = self.modulation_hz;
            let (kernel, reads) = match &frame.black_owed {
                Some(black) => (Kernel::SubtractBlackDemodulate { modulation_hz }, vec![&frame.raw, black]),
                None => (Kernel::Demodulate { modulation_hz }, vec![&frame.raw]),
            };
            let mut planes =
                ctx.device.kernel(ctx.stage, slots(&mut self.kernels, k), kernel, &reads).map_err(|e| e.to_string())?;
            // phase, amplitude, intensity, distance
            let distance = planes.pop().expect("four outputs");
            let intensity = planes.pop().expect("four outputs");
            let amplitude = planes.pop().expect("four outputs");
            out.push((
                "DepthOut".to_string(),
                Data::Depth(DepthImage {
                    distance,
                    amplitude,
                    intensity,
                    truth: frame.truth.clone(),
                    integration_us: frame.integration_us,
                    stamp: frame.stamp,
                }),
            ));
        }
        Ok(out)
    }
}

/// `ToF.MotionCompensation`: optional phase normalization (a calibration file), detection (θ)
/// and block matching (MWS, restricted to ρ around the previous frame's mean direction, whole
/// or quarter pixels) on the normalised frame, optional direction smoothing (NH), correction of
/// the normalised frame (the raw one without a calibration): the correction moves each phase
/// image's charges to another pixel, so the pixels' own gains must be undone first or they
/// travel with them.
pub struct MotionCompensation {
    window: u32,
    theta: f32,
    /// Half of ρ in radians, when restricted.
    half_rho: Option<f32>,
    /// θ as written, in percent.
    theta_percent: f32,
    smooth: bool,
    subpixel: bool,
    /// The phase-normalization calibration (8 planes), if given, and its upload.
    calibration: Option<Image>,
    uploaded: BufferSlot,
    /// Per item position: the kernels, and the previous frame's mean direction.
    items: Vec<MotionItem>,
}

#[derive(Default)]
struct MotionItem {
    normalize: KernelSlot,
    /// Detection and matching, fused.
    matching: KernelSlot,
    smooth: KernelSlot,
    correct: KernelSlot,
    /// With ρ: the mean direction of this frame's flow, on the device.
    mean: KernelSlot,
    /// With ρ: the direction the next frame's search is restricted around (none known before
    /// a frame moved), kept on the device from frame to frame.
    direction: Option<Tensor>,
    direction_slot: BufferSlot,
}

impl MotionCompensation {
    pub fn new(params: &Params) -> Result<MotionCompensation, Vec<PipelineError>> {
        let rho = params.f32("directionRestriction");
        let calibration = match params.file("phaseCalibration") {
            Some(path) => Some(
                params
                    .files
                    .folder(&path)
                    .map_err(|e| e.to_string())
                    .and_then(|folder| PhaseCalibration::load(folder, &path).map_err(|e| e.to_string()))
                    .map_err(|e| vec![params.error("phaseCalibration", ErrorKind::Input, e)])?
                    .coefficients,
            ),
            None => None,
        };
        Ok(MotionCompensation {
            window: params.count("windowSize") as u32,
            theta: params.f32("threshold") / 100.0 * 65535.0,
            half_rho: (rho > 0.0).then(|| (rho / 2.0).to_radians()),
            theta_percent: params.f32("threshold"),
            smooth: params.flag("smoothNeighbourhood"),
            subpixel: params.flag("subpixel"),
            calibration,
            uploaded: BufferSlot::default(),
            items: Vec::new(),
        })
    }
}

impl Component for MotionCompensation {
    /// ρ needs a previous frame; θ = 0 takes every pixel for moving.
    fn cannot_act(&self, frames: usize) -> Option<(&'static str, String)> {
        if self.half_rho.is_some() && frames <= 1 {
            let why = "ρ restricts the flow to directions around the previous frame's mean direction: a run of one \
                       frame has no previous frame, so it does nothing";
            return Some(("directionRestriction", why.into()));
        }
        if self.theta_percent == 0.0 {
            let why = "θ = 0 takes every pixel for moving: static pixels are matched and corrected too (noise \
                       becomes flow); a θ above the noise leaves them as they are";
            return Some(("threshold", why.into()));
        }
        None
    }

    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let Some(calibration) = &self.calibration else { return Ok(()) };
        let own = (calibration.width, calibration.height);
        let advice = "calibrate for this camera";
        of_size(sizes, ("RawIn", "frames"), own, "phaseCalibration", "the phase calibration", advice)
    }

    /// With a calibration, the normalization is the one kernel that reads the frame as it
    /// came: it takes the black image off too (`Kernel::SubtractBlackNormalizePhases`). Without
    /// one, the search would read each sample and its black image many times over.
    fn takes_owed_black(&self) -> bool {
        self.calibration.is_some()
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, frame) in raw_frames(inputs) {
            let item = slots(&mut self.items, k);
            let device = &mut *ctx.device;
            let run = |device: &mut gudsl_runtime::Executor, slot: &mut KernelSlot, kernel, inputs: &[&Tensor]| {
                device.kernel(ctx.stage, slot, kernel, inputs).map_err(|e| e.to_string())
            };
            let normalized = match (&self.calibration, &frame.black_owed) {
                (Some(calibration), owed) => {
                    let calibration = device.upload(&mut self.uploaded, calibration);
                    let (kernel, reads) = match owed {
                        Some(black) => (Kernel::SubtractBlackNormalizePhases, vec![&frame.raw, black, &calibration]),
                        None => (Kernel::NormalizePhases, vec![&frame.raw, &calibration]),
                    };
                    run(device, &mut item.normalize, kernel, &reads)?.remove(0)
                }
                (None, Some(_)) => return Err(OWED.into()),
                (None, None) => frame.raw.clone(),
            };
            // What it gives owes nothing: the black image is off the normalised frame.
            let given = RawFrame { black_owed: None, ..frame.clone() };
            // Detection and matching in one pass (exactly what the two kernels give apart); with
            // ρ around the direction the frame before left on the device.
            let (theta, window, subpixel) = (self.theta, self.window, self.subpixel);
            let matched = match self.half_rho {
                Some(half_width) => {
                    let slot = &mut item.direction_slot;
                    let direction = item.direction.get_or_insert_with(|| device.upload(slot, &no_direction()));
                    let kernel = Kernel::DetectMatchAround { theta, window, half_width, subpixel };
                    run(device, &mut item.matching, kernel, &[&normalized, &*direction])?
                }
                None => {
                    let kernel = Kernel::DetectMatch { theta, window, restriction: None, subpixel };
                    run(device, &mut item.matching, kernel, &[&normalized])?
                }
            };
            let [mut flow, mask]: [Tensor; 2] =
                matched.try_into().map_err(|_| "detection and matching give a flow and a mask".to_string())?;
            if self.smooth {
                flow = run(device, &mut item.smooth, Kernel::SmoothFlow { window: self.window }, &[&flow])?.remove(0);
            }
            let raw = run(device, &mut item.correct, Kernel::CorrectRaw, &[&normalized, &flow])?.remove(0);
            // ρ restricts the next frame around this one's mean direction, kept on the device.
            if let Some(before) = item.direction.take() {
                let mean = run(device, &mut item.mean, Kernel::MeanDirection, &[&flow, &before])?.remove(0);
                item.direction = Some(device.keep(&mut item.direction_slot, &mean));
            }
            // A tap: the flow, to whatever is bound to `FlowOut`.
            out.push(("FlowOut".to_string(), Data::Flow(flow)));
            out.push(("RawOut".to_string(), Data::Raw(RawFrame { raw, ..given.clone() })));
            // A tap: the normalised channels (the frame itself without a calibration).
            out.push(("NormalizedOut".to_string(), Data::Raw(RawFrame { raw: normalized, ..given })));
            // A tap: the motion mask, to whatever is bound to `MaskOut`.
            out.push(("MaskOut".to_string(), Data::Mask(mask)));
        }
        Ok(out)
    }
}

/// The direction of ρ before a frame moved: none known (the search is not restricted).
fn no_direction() -> Image {
    Image { width: 1, height: 1, planes: 2, data: vec![0.0, 0.0] }
}
