//! Which port is which: the library's components read and give data on ports named after its
//! kind (`DepthIn` takes depth images, `CloudOut` gives clouds: `ToF.Components`), and a stage
//! may name its ports otherwise (a port of the user's own component diagram, say an `async`
//! one for a library filter), so its items are handed over under the library's names and what
//! it gives goes out on the stage's ports of that kind.

use gudsl_model::hir::{items::ConnectorRole, pipeline::Stage};

use super::{Carries, Component, Ctx, Inputs, Need, Outputs, Size, SizesByPort};
use crate::pipeline::{data::Data, executor::Reads, OutputDir};

/// The library's data types and the port names its components use for them (`DepthIn`, …).
const KINDS: [(&str, &str); 8] = [
    ("ToF.RawFrame", "Raw"),
    ("ToF.DepthImage", "Depth"),
    ("ToF.Mask", "Mask"),
    ("ToF.FlowField", "Flow"),
    ("ToF.PointCloud", "Cloud"),
    ("ToF.Pose", "Pose"),
    ("ToF.IntegrationTime", "Time"),
    ("ToF.RgbaImage", "Image"),
];

/// The kind of a port whose data the library does not know.
const UNKNOWN: &str = "Unknown";

/// The port a library component reads data of `kind` on (`DepthIn`).
pub fn input_port(kind: &str) -> String {
    format!("{kind}In")
}

/// The port a library component gives data of `kind` on (`DepthOut`).
fn output_port(kind: &str) -> String {
    format!("{kind}Out")
}

pub fn kind_of(data: &Data) -> &'static str {
    match data {
        Data::Raw(_) => "Raw",
        Data::Depth(_) => "Depth",
        Data::Mask(_) => "Mask",
        Data::Flow(_) => "Flow",
        Data::Cloud(_) => "Cloud",
        Data::Pose(_) => "Pose",
        Data::IntegrationTime(_) => "Time",
        Data::Image(_) => "Image",
    }
}

/// The stage's ports with a connector of `role`, with the kind of data each carries.
pub fn port_kinds(stage: &Stage, role: ConnectorRole) -> Vec<(String, &'static str)> {
    stage
        .ports
        .iter()
        .filter_map(|port| {
            let connector = port.connectors.iter().find(|c| c.role == role)?;
            // What no library type names (a type of the workspace's own) is data no component
            // of the library makes or takes.
            let kind = KINDS.iter().find(|(ty, _)| connector.carries.iter().any(|t| t == ty)).map_or(UNKNOWN, |k| k.1);
            Some((port.name.clone(), kind))
        })
        .collect()
}

/// `component`, a library component, on `stage`'s ports: as it is where they have the
/// library's names.
pub fn on_stage_ports(component: Box<dyn Component>, stage: &Stage) -> Box<dyn Component> {
    let receives = port_kinds(stage, ConnectorRole::Processor);
    let providers = port_kinds(stage, ConnectorRole::Provider);
    let library_named = |ports: &[(String, &str)], name: fn(&str) -> String| {
        ports.iter().all(|(port, kind)| *kind == UNKNOWN || *port == name(kind))
    };
    if library_named(&receives, input_port) && library_named(&providers, output_port) {
        return component;
    }
    Box::new(OnStagePorts { component, receives, providers })
}

/// A library component on ports of other names.
struct OnStagePorts {
    component: Box<dyn Component>,
    receives: Vec<(String, &'static str)>,
    providers: Vec<(String, &'static str)>,
}

impl OnStagePorts {
    /// The library's name for the stage's processor port `port`.
    fn library_input(&self, port: &str) -> String {
        match self.receives.iter().find(|(p, _)| p == port) {
            Some((_, kind)) if *kind != UNKNOWN => input_port(kind),
            _ => port.to_string(),
        }
    }

    /// What the component gave on the library's ports, on the stage's ports of each kind.
    fn on_stage_ports(&self, given: Outputs) -> Outputs {
        let mut out = Vec::new();
        for (library_port, data) in given {
            let ports: Vec<&String> = self
                .providers
                .iter()
                .filter(|(port, kind)| output_port(kind) == library_port || *port == library_port)
                .map(|(port, _)| port)
                .collect();
            out.extend(ports.into_iter().map(|port| (port.clone(), data.clone())));
        }
        out
    }
}

impl Component for OnStagePorts {
    fn frames(&self) -> Option<usize> {
        self.component.frames()
    }

    fn image_size(&self) -> Option<Size> {
        self.component.image_size()
    }

    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let mut renamed = SizesByPort::new();
        for (port, set) in sizes {
            renamed.entry(self.library_input(port)).or_default().extend(set);
        }
        self.component.sizes_meet(&renamed)
    }

    fn carries(&self, arriving: Carries) -> Carries {
        self.component.carries(arriving)
    }

    fn needs(&self) -> Option<Need> {
        self.component.needs()
    }

    fn cannot_act(&self, frames: usize) -> Option<(&'static str, String)> {
        self.component.cannot_act(frames)
    }

    fn too_short(&self, frames: usize) -> Option<(&'static str, String)> {
        self.component.too_short(frames)
    }

    fn load(&mut self) -> Result<(), String> {
        self.component.load()
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut renamed = Inputs::default();
        for (port, items) in inputs.by_port() {
            for item in items {
                renamed.push(&self.library_input(port), item.clone());
            }
        }
        let given = self.component.process(ctx, &renamed)?;
        Ok(self.on_stage_ports(given))
    }

    fn feeds_back(&self) -> bool {
        self.component.feeds_back()
    }

    fn takes_owed_black(&self) -> bool {
        self.component.takes_owed_black()
    }

    fn owe_black(&mut self, owe: bool) -> bool {
        self.component.owe_black(owe)
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        let given = self.component.finish_frame(ctx, reads)?;
        Ok(self.on_stage_ports(given))
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        self.component.finish_run(output)
    }

    fn figures(&self) -> Vec<(String, f64)> {
        self.component.figures()
    }
}
