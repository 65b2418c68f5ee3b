//! Calc and calcRange nodes on the device: a kernel launched with the node's work sizes (calc:
//! global sizes x, y, z, a zero ends the dimensions; the local size is the launcher's choice)
//! or ranges (calcRange: the global and then the local size of each of 1–3 dimensions), the
//! containers' device memory bound to image and buffer parameters, values and `shared` sizes
//! (bytes) to the others; what each calc node took, for the report.

use std::{cell::Ref, time::Duration};

use gudsl_codegen::Binding;
use gudsl_runtime::TexelFormat;

use super::{
    ir::NodeKind,
    machine::Machine,
    value::{Object, Value},
    CalcReport,
};
use crate::launch::{Arg, Number, WorkRange};

impl Machine<'_, '_> {
    /// Launches kernel `index` with `args` over the current node's work; the device's time.
    pub(super) fn launch(&mut self, index: usize, args: &[Value]) -> Result<Duration, String> {
        let launcher = &self.launchers[index];
        let kernel = launcher.kernel();
        let gpu = self.framework.gpu;
        let node = &self.program.nodes[self.node];
        let range = work_range(node.kind, &self.work).map_err(|m| format!("`{}`: {m}", node.name))?;
        if args.len() != kernel.params.len() {
            return Err(format!(
                "{} argument(s) for `{}`, which takes {}",
                args.len(),
                kernel.diagram,
                kernel.params.len()
            ));
        }
        // Device memory first (made where the diagram never synchronised a container).
        for (param, arg) in kernel.params.iter().zip(args) {
            let wrong = |what: &str| format!("`{}` takes {what}, not a {}", param.name, arg.kind());
            match (&param.binding, arg) {
                (Binding::Image { image, .. }, Value::Object(object)) => match &mut *object.borrow_mut() {
                    Object::Images(container) => {
                        let wanted = TexelFormat::from_wgsl(image.format);
                        if wanted != Some(container.format()?) {
                            return Err(format!(
                                "`{}` is an image of {} texels; the container `{}` holds {:?} texels",
                                param.name, image.format, container.label, container.element
                            ));
                        }
                        container.device(gpu)?;
                    }
                    _ => return Err(wrong("an ImageContainer")),
                },
                (Binding::Image { .. }, _) => return Err(wrong("an ImageContainer")),
                (Binding::Storage { .. }, Value::Object(object)) => match &mut *object.borrow_mut() {
                    Object::Buffer(container) => {
                        container.device(gpu)?;
                    }
                    _ => return Err(wrong("a BufferContainer")),
                },
                (Binding::Storage { .. }, _) => {
                    return Err(wrong("a BufferContainer (host memory is not on the device)"))
                }
                _ => {}
            }
        }
        let guards: Vec<Option<Ref<Object>>> =
            args.iter().map(|a| if let Value::Object(o) = a { Some(o.borrow()) } else { None }).collect();
        let mut launch_args = Vec::with_capacity(args.len());
        for ((param, arg), guard) in kernel.params.iter().zip(args).zip(&guards) {
            let launch_arg = match (&param.binding, guard.as_deref()) {
                (Binding::Image { .. }, Some(Object::Images(c))) => Arg::Image(c.device.as_ref().expect("made above")),
                (Binding::Storage { .. }, Some(Object::Buffer(c))) => {
                    Arg::Buffer(c.device.as_ref().expect("made above"))
                }
                (Binding::Uniform { .. } | Binding::Workgroup { .. }, _) => Arg::Number(match arg {
                    Value::Int(v) => Number::Int(*v as i64),
                    Value::UInt(v) => Number::UInt(*v as u64),
                    Value::Float(v) => Number::Float(*v),
                    Value::Bool(v) => Number::Bool(*v),
                    other => return Err(format!("`{}` takes a number, not a {}", param.name, other.kind())),
                }),
                _ => return Err(format!("`{}` cannot take a {}", param.name, arg.kind())),
            };
            launch_args.push(launch_arg);
        }
        launcher.launch(gpu, &launch_args, &range).map_err(|e| e.to_string())
    }

    /// Adds a launch of kernel `index` by the current node to the report.
    pub(super) fn record(&mut self, index: usize, device: Duration, wall: Duration) {
        let node = &self.program.nodes[self.node].name;
        let kernel = &self.launchers[index].kernel().diagram;
        match self.calcs.iter_mut().find(|c| &c.node == node && &c.kernel == kernel) {
            Some(calc) => {
                calc.launches += 1;
                calc.device += device;
                calc.wall += wall;
            }
            None => {
                self.calcs.push(CalcReport { node: node.clone(), kernel: kernel.clone(), launches: 1, device, wall })
            }
        }
        self.observer.launched(node, kernel, device);
    }
}

/// The work of a launch from a calc node's sizes or a calcRange node's ranges.
fn work_range(kind: NodeKind, work: &[i64]) -> Result<WorkRange, String> {
    let size = |v: i64, what: &str| {
        u32::try_from(v).ok().filter(|v| *v > 0).ok_or_else(|| format!("a {what} of {v} work-items"))
    };
    match (kind, work) {
        (NodeKind::Calc, [x, y, z]) => {
            let dimensions = if *z > 0 {
                3
            } else if *y > 0 {
                2
            } else {
                1
            };
            let global = [size(*x, "global size")?, (*y).max(1) as u32, (*z).max(1) as u32];
            Ok(WorkRange { dimensions, global, local: None })
        }
        (NodeKind::CalcRange, ranges) if matches!(ranges.len(), 2 | 4 | 6) => {
            let dimensions = ranges.len() / 2;
            let mut global = [1; 3];
            let mut local = [1; 3];
            for d in 0..dimensions {
                global[d] = size(ranges[d], "global size")?;
                local[d] = size(ranges[dimensions + d], "local size")?;
            }
            Ok(WorkRange { dimensions: dimensions as u32, global, local: Some(local) })
        }
        (NodeKind::Calc | NodeKind::CalcRange, _) => {
            Err("entered without work sizes: a transition into a calc node passes them".into())
        }
        _ => Err("kernels are launched from calc and calcRange nodes".into()),
    }
}
