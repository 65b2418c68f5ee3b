//! Components of the workspace (chapter 11.5's `Camera`, `MeanFilter`, `Viewer`): a class that
//! extends a library component runs as it, and the device diagrams its own `process` calls
//! (`call behavior AdFilterMean;`, generated as WGSL by `gudsl-codegen`) run on the images
//! (`ToF.RgbaImage`) it gives — a source's or a filter's — or, for a sink, on those it is given.
//! A filter that extends nothing gives what it receives, through its diagrams.
//!
//! A diagram's parameters are taken from the caller, as `call behavior` without arguments takes
//! them (Sec. 10.2): an image it only reads is the image at hand, the image it writes the next
//! one, and a value parameter is the component's field of that name. Each diagram runs over the
//! image's pixels (a 2D global size of width × height), recorded into the frame's encoder
//! between the runtime's kernels; images cross into the generated code as `image2D_uc`
//! textures and back into the pipeline's planes (`texels.rs`). On depth images (`ToF.DepthImage`)
//! a diagram's `global ref float` buffers named `distance`, `amplitude` and `intensity` are the
//! image's planes (the distance the diagram before wrote), and the one it writes is the next
//! distance.

use std::collections::HashMap;

use gudsl_codegen::{Binding, Kernel};
use gudsl_model::{
    ast::ClassKind,
    hir::{
        items::ConnectorRole,
        pipeline::{PipelinePlan, Value},
        Semantics, Ty,
    },
};
use gudsl_runtime::{executor::BufferSlot, DeviceImage, Gpu, TexelFormat};

use super::{
    ports::{input_port, kind_of, port_kinds},
    slots,
    texels::Conversions,
    Carries, Component, Ctx, Inputs, Need, Outputs, Params, Size, SizesByPort,
};
use crate::{
    launch::{Arg, Launcher, Number, WorkRange},
    pipeline::{
        data::{Data, DepthImage, Item, Picture, Tensor},
        executor::Reads,
        ErrorKind, OutputDir, PipelineError,
    },
};

/// The generated kernels of the diagrams the pipeline's components call, by fully qualified
/// name, or why one cannot be generated.
pub type Behaviors = HashMap<String, Result<Kernel, String>>;

/// A workspace component with its library base (if any) and the diagrams its `process` runs.
pub struct WorkspaceComponent {
    instance: String,
    kind: ClassKind,
    base: Option<Box<dyn Component>>,
    steps: Vec<Step>,
    /// The stage's provider and processor ports, with the kind of data each carries.
    providers: Vec<(String, &'static str)>,
    receives: Vec<(String, &'static str)>,
    /// Per item of a frame: its textures and the planes it goes back into.
    slots: Vec<ItemSlot>,
    conversions: Option<Conversions>,
}

/// One diagram of `process`: its kernel, compiled on the first frame, and its arguments.
struct Step {
    kernel: Kernel,
    launcher: Option<Launcher>,
    args: Vec<StepArg>,
}

#[derive(Clone, Copy)]
enum StepArg {
    Value(Number),
    /// The image at hand.
    Read,
    /// The image it writes.
    Written,
    /// A plane of the depth image at hand (0 distance, 1 amplitude, 2 intensity; the distance
    /// the previous diagram wrote).
    Plane(usize),
}

/// The depth image's planes a diagram reads by name, in `StepArg::Plane`'s order.
const PLANES: [&str; 3] = ["distance", "amplitude", "intensity"];

#[derive(Default)]
struct ItemSlot {
    input: Option<DeviceImage>,
    outputs: Vec<DeviceImage>,
    planes: BufferSlot,
    /// The distance each diagram writes, for depth images.
    distances: Vec<BufferSlot>,
}

/// A workspace component of `base` (the library component it extends, made from the same
/// parameters), or why it cannot run.
pub fn make(
    params: &Params,
    base: Option<Box<dyn Component>>,
    behaviors: &Behaviors,
) -> Result<Box<dyn Component>, Vec<PipelineError>> {
    let stage = params.stage;
    let not_runnable = |message: String| vec![params.stage_error(ErrorKind::NotRunnable, message)];
    if base.is_none() && stage.behavior.is_empty() {
        return Err(not_runnable(format!(
            "`{}` is not a component of the ToF library, extends none and its `process` calls no device diagram: nothing to run",
            stage.class
        )));
    }
    if base.is_none() && stage.kind == ClassKind::Sink {
        return Err(not_runnable(format!(
            "`{}` is a sink that extends no sink of the ToF library: nothing would keep what it is given (extend `ToF.ImageViewer` to write its images)",
            stage.class
        )));
    }
    let providers = port_kinds(stage, ConnectorRole::Provider);
    let receives = port_kinds(stage, ConnectorRole::Processor);
    // The diagrams run on what a sink is given, on what a source or a filter gives.
    let worked_on = if stage.kind == ClassKind::Sink { &receives } else { &providers };
    let on = worked_on.first().map_or("Image", |(_, kind)| *kind);
    if !stage.behavior.is_empty() && (!["Image", "Depth"].contains(&on) || worked_on.iter().any(|(_, k)| *k != on)) {
        let what = if stage.kind == ClassKind::Sink { "is given" } else { "gives" };
        return Err(not_runnable(format!(
            "`{}` runs device diagrams, which run on images (`ToF.RgbaImage`) or depth images (`ToF.DepthImage`); it {what} other data",
            stage.class
        )));
    }
    let mut steps = Vec::new();
    let mut errors = Vec::new();
    for call in &stage.behavior {
        let diagram = &call.diagram;
        if !call.plain {
            errors.extend(not_runnable(format!(
                "`process` calls `{diagram}` with arguments or inside a branch or loop; a component runs the diagrams its `process` calls as statements of their own, `call behavior {diagram};`, in order"
            )));
            continue;
        }
        match behaviors.get(diagram) {
            Some(Ok(kernel)) => match step(params, kernel, on == "Depth") {
                Ok(step) => steps.push(step),
                Err(mut problems) => errors.append(&mut problems),
            },
            Some(Err(why)) => errors.extend(not_runnable(why.clone())),
            None => errors.extend(not_runnable(format!("`{diagram}` was not generated"))),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Box::new(WorkspaceComponent {
        instance: stage.instance.clone(),
        kind: stage.kind,
        base,
        steps,
        providers,
        receives,
        slots: Vec::new(),
        conversions: None,
    }))
}

/// A diagram's kernel with its arguments taken from the component, or what does not fit: on
/// images (`image2D_uc` read and written) or, `on_depth`, on depth images (`global ref float`
/// buffers: `distance`, `amplitude`, `intensity` read, one written — the next distance).
fn step(params: &Params, kernel: &Kernel, on_depth: bool) -> Result<Step, Vec<PipelineError>> {
    let stage = params.stage;
    let diagram = kernel.diagram.rsplit('.').next().unwrap_or(&kernel.diagram);
    let error =
        |kind, message: String| params.stage_error(kind, format!("`{diagram}` (called by `process`): {message}"));
    let mut args = Vec::new();
    let mut errors = Vec::new();
    for param in &kernel.params {
        let name = &param.name;
        match &param.binding {
            Binding::Image { .. } if on_depth => errors.push(error(
                ErrorKind::NotRunnable,
                format!("its image `{name}` is no plane of a depth image; it works on `global ref float` buffers named {} and one it writes", PLANES.join(", ")),
            )),
            Binding::Storage { writable, .. } if on_depth => {
                let plane = PLANES.iter().position(|p| p == name);
                match (writable, plane) {
                    _ if *param.ty.dereferenced() != Ty::Float => errors.push(error(
                        ErrorKind::NotRunnable,
                        format!("its buffer `{name}` is a `{}`; a depth image's planes are `global ref float`", param.ty),
                    )),
                    (true, _) => args.push(StepArg::Written),
                    (false, Some(plane)) => args.push(StepArg::Plane(plane)),
                    (false, None) => errors.push(error(
                        ErrorKind::NotRunnable,
                        format!("it reads a buffer `{name}`; a depth image's planes are {}", PLANES.join(", ")),
                    )),
                }
            }
            Binding::Image { image, read, written, .. } => {
                if image.format != "rgba8uint" || image.dimensions != 2 {
                    errors.push(error(
                        ErrorKind::NotRunnable,
                        format!("its image `{name}` is a `{}`; a component's images are `image2D_uc`", param.ty),
                    ));
                }
                if *read && *written {
                    errors.push(error(
                        ErrorKind::NotRunnable,
                        format!("it reads and writes its image `{name}`; a component's diagram reads the image at hand from one image parameter and writes the next into another"),
                    ));
                }
                args.push(if *written { StepArg::Written } else { StepArg::Read });
            }
            Binding::Uniform { .. } => match stage.param(name) {
                Some(value) => match number(value) {
                    Some(number) => args.push(StepArg::Value(number)),
                    None => errors.push(error(
                        ErrorKind::Mismatch,
                        format!("the field `{name}` of `{}` is no number for its parameter `{name}`", stage.class),
                    )),
                },
                None => errors.push(error(
                    ErrorKind::Mismatch,
                    format!(
                        "it takes `{} {name}`, and `{}` has no field `{name}` to give it (a diagram called without arguments takes its parameters from the component's fields)",
                        param.ty, stage.class
                    ),
                )),
            },
            Binding::Storage { .. } | Binding::Workgroup { .. } => errors.push(error(
                ErrorKind::NotRunnable,
                format!("its parameter `{name}` (`{}`) is memory a component cannot give; only images and values (buffers on depth images)", param.ty),
            )),
        }
    }
    match args.iter().filter(|a| matches!(a, StepArg::Written)).count() {
        0 => errors.push(error(ErrorKind::NotRunnable, "it writes nothing: nothing would come out of it".into())),
        1 => {}
        n => errors.push(error(
            ErrorKind::NotRunnable,
            format!("it writes {n} images or buffers; a component's diagram writes one, what it gives on"),
        )),
    }
    if errors.is_empty() {
        Ok(Step { kernel: kernel.clone(), launcher: None, args })
    } else {
        Err(errors)
    }
}

/// A field's value as a kernel takes it (a missing one is C++'s zero).
fn number(value: &Value) -> Option<Number> {
    match value {
        Value::Int(v) => Some(Number::Int(*v)),
        Value::Float(v) => Some(Number::Float(v.get())),
        Value::Bool(v) => Some(Number::Bool(*v)),
        Value::Missing => Some(Number::Int(0)),
        Value::Text(_) | Value::Enum(_) => None,
    }
}

impl Component for WorkspaceComponent {
    fn frames(&self) -> Option<usize> {
        self.base.as_ref().and_then(|b| b.frames())
    }

    fn image_size(&self) -> Option<Size> {
        self.base.as_ref().and_then(|b| b.image_size())
    }

    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let Some(base) = &self.base else { return Ok(()) };
        // The base reads its inputs on its own ports, named after what they carry.
        let mut renamed = SizesByPort::new();
        for (port, set) in sizes {
            let kind = self.receives.iter().find(|(p, _)| p == port).map_or("Image", |(_, kind)| *kind);
            renamed.entry(input_port(kind)).or_default().extend(set);
        }
        base.sizes_meet(&renamed)
    }

    fn carries(&self, arriving: Carries) -> Carries {
        self.base.as_ref().map_or(arriving, |b| b.carries(arriving))
    }

    fn needs(&self) -> Option<Need> {
        self.base.as_ref().and_then(|b| b.needs())
    }

    fn cannot_act(&self, frames: usize) -> Option<(&'static str, String)> {
        self.base.as_ref().and_then(|b| b.cannot_act(frames))
    }

    fn too_short(&self, frames: usize) -> Option<(&'static str, String)> {
        self.base.as_ref().and_then(|b| b.too_short(frames))
    }

    fn load(&mut self) -> Result<(), String> {
        self.base.as_mut().map_or(Ok(()), |b| b.load())
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let items: Vec<&Item> = inputs.all().collect();
        if self.kind == ClassKind::Sink {
            let mut given = Inputs::default();
            for (k, item) in items.into_iter().enumerate() {
                let data = self.through_diagrams(ctx, k, &item.data)?;
                given.push(&input_port(kind_of(&data)), Item { data, ..item.clone() });
            }
            return self.base.as_mut().expect("a sink has a base").process(ctx, &given);
        }
        let produced: Vec<Data> = match &mut self.base {
            Some(base) => {
                let mut given = Inputs::default();
                for item in items {
                    given.push(&input_port(kind_of(&item.data)), item.clone());
                }
                base.process(ctx, &given)?.into_iter().map(|(_, data)| data).collect()
            }
            None => items.into_iter().map(|item| item.data.clone()).collect(),
        };
        let mut out = Vec::new();
        for (k, data) in produced.iter().enumerate() {
            let data = self.through_diagrams(ctx, k, data)?;
            out.extend(self.on_ports(data));
        }
        Ok(out)
    }

    fn feeds_back(&self) -> bool {
        self.base.as_ref().is_some_and(|base| base.feeds_back())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        let Some(base) = &mut self.base else { return Ok(Vec::new()) };
        let given = base.finish_frame(ctx, reads)?;
        Ok(given.into_iter().flat_map(|(_, data)| self.on_ports(data)).collect())
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        self.base.as_mut().map_or(Ok(()), |b| b.finish_run(output))
    }

    fn figures(&self) -> Vec<(String, f64)> {
        self.base.as_ref().map_or_else(Vec::new, |b| b.figures())
    }
}

impl WorkspaceComponent {
    /// `data` on each provider port that carries its kind.
    fn on_ports(&self, data: Data) -> Outputs {
        let kind = kind_of(&data);
        self.providers.iter().filter(|(_, k)| *k == kind).map(|(port, _)| (port.clone(), data.clone())).collect()
    }

    /// `data` through `process`'s diagrams, in order (the `k`-th item of the frame).
    fn through_diagrams(&mut self, ctx: &mut Ctx, k: usize, data: &Data) -> Result<Data, String> {
        if self.steps.is_empty() || !matches!(data, Data::Image(_) | Data::Depth(_)) {
            return Ok(data.clone());
        }
        let Some(gpu) = ctx.device.gpu() else {
            let names: Vec<&str> = self.steps.iter().map(|s| s.kernel.diagram.as_str()).collect();
            return Err(format!(
                "`{}` runs device diagrams ({}) generated as WGSL: they need a GPU adapter (lavapipe is one), and this run has none",
                self.instance,
                names.join(", ")
            ));
        };
        for step in &mut self.steps {
            if step.launcher.is_none() {
                step.launcher = Some(Launcher::new(gpu, &step.kernel).map_err(|e| e.to_string())?);
            }
        }
        match data {
            Data::Depth(depth) => self.through_depth_diagrams(ctx, k, depth),
            Data::Image(picture) => self.through_image_diagrams(ctx, gpu, k, picture),
            _ => unreachable!("checked above"),
        }
    }

    /// A depth image through the diagrams: each reads the planes it names, the distance the one
    /// before wrote, and writes the next distance.
    fn through_depth_diagrams(&mut self, ctx: &mut Ctx, k: usize, depth: &DepthImage) -> Result<Data, String> {
        let shape = depth.distance.shape();
        let slot = slots(&mut self.slots, k);
        slot.distances.resize_with(self.steps.len(), BufferSlot::default);
        let on_gpu = "a depth image in host memory on a GPU run";
        let buffer = |tensor: &Tensor| tensor.device_buffer().ok_or_else(|| on_gpu.to_string());
        let mut planes = [buffer(&depth.distance)?, buffer(&depth.amplitude)?, buffer(&depth.intensity)?];
        let mut distance = depth.distance.clone();
        for (step, written) in self.steps.iter().zip(&mut slot.distances) {
            distance = ctx.device.buffer(written, shape).ok_or_else(|| on_gpu.to_string())?;
            let written = buffer(&distance)?;
            let args: Vec<Arg> = step
                .args
                .iter()
                .map(|arg| match arg {
                    StepArg::Value(number) => Arg::Number(*number),
                    StepArg::Plane(plane) => Arg::Buffer(&planes[*plane]),
                    StepArg::Written | StepArg::Read => Arg::Buffer(&written),
                })
                .collect();
            let launcher = step.launcher.as_ref().expect("compiled before");
            let range = WorkRange::planar(shape.width as u32, shape.height as u32, None);
            launcher.record(ctx.device, ctx.stage, &args, &range).map_err(|e| e.to_string())?;
            planes[0] = written;
        }
        Ok(Data::Depth(DepthImage { distance, ..depth.clone() }))
    }

    /// An RGBA image through the diagrams, as a texture between its planes.
    fn through_image_diagrams(
        &mut self,
        ctx: &mut Ctx,
        gpu: &Gpu,
        k: usize,
        picture: &Picture,
    ) -> Result<Data, String> {
        let shape = picture.texels.shape();
        let Some(texels) = picture.texels.device_buffer() else {
            return Err("an image in host memory on a GPU run".into());
        };
        let size = [shape.width as u32, shape.height as u32, 1];
        let conversions = match &mut self.conversions {
            Some(c) => c,
            None => self.conversions.insert(Conversions::new(gpu).map_err(|e| e.to_string())?),
        };
        let slot = slots(&mut self.slots, k);
        let image = |gpu: &Gpu| DeviceImage::new(gpu, "component image", TexelFormat::Rgba8Uint, 2, size);
        if slot.input.as_ref().is_none_or(|i| i.size() != size) {
            slot.input = Some(image(gpu).map_err(|e| e.to_string())?);
            slot.outputs.clear();
        }
        while slot.outputs.len() < self.steps.len() {
            slot.outputs.push(image(gpu).map_err(|e| e.to_string())?);
        }
        let planes = ctx.device.buffer(&mut slot.planes, shape).ok_or("an image in host memory on a GPU run")?;
        let input = slot.input.as_ref().expect("made above");
        conversions.pack(ctx, &texels, input)?;
        let mut current = input;
        for (step, output) in self.steps.iter().zip(&slot.outputs) {
            let args: Vec<Arg> = step
                .args
                .iter()
                .map(|arg| match arg {
                    StepArg::Value(number) => Arg::Number(*number),
                    StepArg::Read | StepArg::Plane(_) => Arg::Image(current),
                    StepArg::Written => Arg::Image(output),
                })
                .collect();
            let launcher = step.launcher.as_ref().expect("compiled before");
            let range = WorkRange::planar(size[0], size[1], None);
            launcher.record(ctx.device, ctx.stage, &args, &range).map_err(|e| e.to_string())?;
            current = output;
        }
        let device_planes = planes.device_buffer().ok_or("an image in host memory on a GPU run")?;
        conversions.unpack(ctx, current, &device_planes)?;
        Ok(Data::Image(Picture { texels: planes, source: picture.source.clone() }))
    }
}

/// The kernels of the device diagrams the plan's workspace components call in `process`
/// (generated once, here, where the model is: a run needs no database).
pub fn behaviors(sema: &Semantics, plan: &PipelinePlan) -> Behaviors {
    let mut behaviors = Behaviors::new();
    if plan.stages.iter().all(|s| s.behavior.is_empty()) {
        return behaviors; // the editor asks at every change: no scan of the workspace for none
    }
    let device = gudsl_codegen::device_diagrams(sema);
    for fqn in plan.stages.iter().flat_map(|s| &s.behavior).map(|call| &call.diagram) {
        if behaviors.contains_key(fqn) {
            continue;
        }
        let kernel = match device.iter().find(|d| &d.fqn == fqn) {
            Some(def) => gudsl_codegen::generate(sema, def).map_err(|errors| {
                let first = errors.first().map_or("", |e| e.message.as_str());
                format!("`{fqn}` cannot be generated as WGSL: {first} (`gudsl wgsl` lists every problem)")
            }),
            None => Err(format!(
                "`{fqn}` is not a device diagram (no class implementing `OpenCL` owns it): a component's `process` runs device diagrams"
            )),
        };
        behaviors.insert(fqn.clone(), kernel);
    }
    behaviors
}
