//! Sources: the simulated PMD camera (`ToF.SimulatedCamera`, and `ToF.ControlledCamera`, which
//! takes each frame at the last integration time it received), raw frames made by the
//! runtime's simulator on the host and uploaded where the kernels run; recorded raw frames
//! (`ToF.RawFrameFile`), depth images (`ToF.DepthFile`) and point clouds (`ToF.CloudFile`)
//! read from files.

use std::sync::Arc;

use gudsl_runtime::{
    camera::{pose_from, Intrinsics},
    sim::{simulate_unless, Camera, Motion, Scene},
};

use gudsl_runtime::Image;

use super::{raw::open_raw_files, Carries, Component, Ctx, Inputs, Outputs, Params, Size};
use crate::pipeline::{
    data::{Data, DepthImage, PointCloud, RawFrame},
    executor::BufferSlot,
    files::{self, Extent, RawFiles},
    ErrorKind, PipelineError,
};

/// A simulated camera and its scene.
pub struct Simulated {
    scene: Scene,
    /// The scene before the object appears (for a background model).
    empty: Scene,
    empty_frames: usize,
    motion: Motion,
    camera: Camera,
    frames: usize,
    /// Integration times arrive on `TimeIn` (a `ControlledCamera`).
    controlled: bool,
    raw: BufferSlot,
    black: BufferSlot,
    /// Whether its frames carry the black image (a grey-value camera demodulates without it).
    pub gives_black: bool,
}

impl Simulated {
    pub fn new(params: &Params, controlled: bool) -> Simulated {
        let wall = |scene: Scene| Scene {
            wall_distance: params.f32("wallDistance"),
            wall_reflectivity: params.f32("wallReflectivity"),
            object_reflectivity: params.f32("objectReflectivity"),
            ..scene
        };
        let scene = wall(match params.member("scene") {
            "Box" => Scene::cuboid(),
            "TurnedBox" => Scene::turned_box(),
            "Relief" => Scene::height_field(),
            "Plates" => Scene::plates(),
            "Wall" => Scene::empty(),
            _ => Scene::sphere(),
        });
        let speed = params.f32("speed");
        let motion = match params.member("motion") {
            "Translation" => Motion::Translation([speed / 100.0, 0.0, 0.0]),
            "Rotation" => Motion::Rotation(speed),
            _ => Motion::Still,
        };
        let degrees = |name: &str| params.number(name).to_radians();
        let pose = pose_from(
            [degrees("pitch"), degrees("yaw"), degrees("roll")],
            [params.number("x"), params.number("y"), params.number("z")],
        );
        let camera = Camera {
            intrinsics: Intrinsics::camcube_at(params.count("width"), params.count("height")),
            modulation_hz: params.f32("modulationFrequency") * 1e6,
            integration_us: params.f32("integrationTime"),
            noise: params.flag("noise"),
            supersampling: params.count("supersampling").max(1),
            gain_spread: params.f32("gainSpread"),
            seed: params.number("seed") as i64 as u64,
            pose,
            ..Camera::default()
        };
        Simulated {
            empty: Scene { object: None, ..scene },
            scene,
            empty_frames: params.count("emptyFrames"),
            motion,
            camera,
            frames: params.count("frames"),
            controlled,
            raw: BufferSlot::default(),
            black: BufferSlot::default(),
            gives_black: true,
        }
    }
}

impl Component for Simulated {
    fn frames(&self) -> Option<usize> {
        Some(self.frames)
    }

    /// The scene's true distances always; the black image unless it is a grey-value camera's.
    fn carries(&self, _arriving: Carries) -> Carries {
        Carries { black: self.gives_black, truth: true, organized: true }
    }

    fn image_size(&self) -> Option<Size> {
        Some((self.camera.intrinsics.width, self.camera.intrinsics.height))
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        if ctx.frame >= self.frames {
            return Ok(Vec::new());
        }
        if self.controlled {
            if let Some(Data::IntegrationTime(t)) = inputs.port("TimeIn").last().map(|i| &i.data) {
                self.camera.integration_us = *t;
            }
        }
        let scene = if ctx.frame < self.empty_frames { &self.empty } else { &self.scene };
        let cancelled = || ctx.cancel.load(std::sync::atomic::Ordering::Relaxed);
        let frame = simulate_unless(scene, self.motion, &self.camera, ctx.frame, &cancelled)
            .ok_or_else(|| format!("cancelled while simulating frame {}", ctx.frame))?;
        let raw = ctx.device.upload(&mut self.raw, &frame.raw);
        let black = self.gives_black.then(|| ctx.device.upload(&mut self.black, &frame.black));
        Ok(vec![(
            "RawOut".to_string(),
            Data::Raw(RawFrame {
                raw,
                black,
                black_owed: None,
                truth: Some(Arc::new(frame.truth)),
                integration_us: self.camera.integration_us,
                stamp: None,
            }),
        )])
    }
}

/// The frames a file source gives: `frames` of the parameter (0: all the file holds), an error
/// at the parameter when the file holds fewer.
fn frames_to_read(params: &Params, extent: Extent) -> Result<usize, Vec<PipelineError>> {
    match params.count("frames") {
        0 => Ok(extent.frames),
        asked if asked <= extent.frames => Ok(asked),
        asked => Err(vec![params.error(
            "frames",
            ErrorKind::Input,
            format!(
                "the file holds {} frame(s) of {}×{}; {asked} are asked for",
                extent.frames, extent.width, extent.height
            ),
        )]),
    }
}

/// `ToF.RawFrameFile`: recorded raw frames, channels A and B.
pub struct RawFrameFile {
    files: RawFiles,
    frames: usize,
    integration_us: f32,
    /// The frames as they are read, once the run started.
    reading: Option<files::RawFrames>,
    raw: BufferSlot,
}

impl RawFrameFile {
    pub fn new(params: &Params) -> Result<RawFrameFile, Vec<PipelineError>> {
        let (a, b) = (params.required_file("channelA"), params.required_file("channelB"));
        let (a, b) = match (a, b) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => return Err(a.err().into_iter().chain(b.err()).flatten().collect()),
        };
        let files = open_raw_files(params, &a, &b)?;
        Ok(RawFrameFile {
            frames: frames_to_read(params, files.extent)?,
            files,
            integration_us: params.f32("integrationTime"),
            reading: None,
            raw: BufferSlot::default(),
        })
    }
}

impl Component for RawFrameFile {
    /// A recording's frames: no black image of their own, no truth.
    fn carries(&self, _arriving: Carries) -> Carries {
        Carries { black: false, truth: false, organized: true }
    }

    fn frames(&self) -> Option<usize> {
        Some(self.frames)
    }

    fn image_size(&self) -> Option<Size> {
        Some((self.files.extent.width, self.files.extent.height))
    }

    fn load(&mut self) -> Result<(), String> {
        self.reading = Some(self.files.frames(self.frames));
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, _inputs: &Inputs) -> Result<Outputs, String> {
        let Some(reading) = self.reading.as_mut().filter(|_| ctx.frame < self.frames) else { return Ok(Vec::new()) };
        let frame = reading.next_frame()?;
        let raw = ctx.device.upload(&mut self.raw, &frame);
        let stamp = reading.stamp;
        let frame =
            RawFrame { raw, black: None, black_owed: None, truth: None, integration_us: self.integration_us, stamp };
        Ok(vec![("RawOut".to_string(), Data::Raw(frame))])
    }
}

/// `ToF.DepthFile`: recorded depth images (no amplitude or intensity: those read as 0).
pub struct DepthFile {
    file: files::DepthFile,
    frames: usize,
    scale: f32,
    /// The images as they are read, once the run started.
    reading: Option<files::DepthFrames>,
    slots: [BufferSlot; 3],
}

impl DepthFile {
    pub fn new(params: &Params) -> Result<DepthFile, Vec<PipelineError>> {
        let path = params.required_file("path")?;
        let file =
            files::DepthFile::open(params.files, &path).map_err(|e| vec![params.error("path", ErrorKind::Input, e)])?;
        Ok(DepthFile {
            frames: frames_to_read(params, file.extent)?,
            file,
            scale: params.f32("scale"),
            reading: None,
            slots: Default::default(),
        })
    }
}

impl Component for DepthFile {
    /// Recorded depth images: no truth.
    fn carries(&self, _arriving: Carries) -> Carries {
        Carries { black: false, truth: false, organized: true }
    }

    fn frames(&self) -> Option<usize> {
        Some(self.frames)
    }

    fn image_size(&self) -> Option<Size> {
        Some((self.file.extent.width, self.file.extent.height))
    }

    fn load(&mut self) -> Result<(), String> {
        self.reading = Some(self.file.frames(self.frames, self.scale));
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, _inputs: &Inputs) -> Result<Outputs, String> {
        let Some(reading) = self.reading.as_mut().filter(|_| ctx.frame < self.frames) else { return Ok(Vec::new()) };
        let distance = &reading.next_frame()?;
        let zeros = Image::zeros(distance.width, distance.height, 1);
        let [d, a, i] = &mut self.slots;
        let depth = DepthImage {
            distance: ctx.device.upload(d, distance),
            amplitude: ctx.device.upload(a, &zeros),
            intensity: ctx.device.upload(i, &zeros),
            truth: None,
            integration_us: 0.0,
            stamp: reading.stamp,
        };
        Ok(vec![("DepthOut".to_string(), Data::Depth(depth))])
    }
}

/// `ToF.CloudFile`: point clouds recorded elsewhere, one a frame (PLY, PCD, a bag's topic).
pub struct CloudFile {
    files: files::CloudFiles,
    frames: usize,
    /// The clouds as they are read, once the run started.
    reading: Option<files::Clouds>,
}

impl CloudFile {
    pub fn new(params: &Params) -> Result<CloudFile, Vec<PipelineError>> {
        let path = params.required_file("path")?;
        let files = files::CloudFiles::open(params.files, &path)
            .map_err(|e| vec![params.error("path", ErrorKind::Input, e)])?;
        let held = files.count;
        let frames = match params.count("frames") {
            0 => held,
            asked if asked <= held => asked,
            asked => {
                let why = format!("{} names {held} cloud(s); {asked} are asked for", path.display());
                return Err(vec![params.error("frames", ErrorKind::Input, why)]);
            }
        };
        Ok(CloudFile { files, frames, reading: None })
    }
}

impl Component for CloudFile {
    /// Clouds of points alone: no image, no truth.
    fn carries(&self, _arriving: Carries) -> Carries {
        Carries { black: false, truth: false, organized: false }
    }

    fn frames(&self) -> Option<usize> {
        Some(self.frames)
    }

    fn load(&mut self) -> Result<(), String> {
        self.reading = Some(self.files.clouds(self.frames));
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, _inputs: &Inputs) -> Result<Outputs, String> {
        let Some(reading) = self.reading.as_mut().filter(|_| ctx.frame < self.frames) else { return Ok(Vec::new()) };
        let (points, normals) = reading.next_cloud()?;
        let cloud = PointCloud::Unorganized { points: Arc::new(points), normals: Arc::new(normals) };
        Ok(vec![("CloudOut".to_string(), Data::Cloud(cloud))])
    }
}
