//! A run's report drawn on its component-instance diagram: under each instance its time per
//! frame (host and GPU) and its share of the stages' time — the slowest marked «slowest», a
//! replayed stage (a live preview's) «replayed», one whose kernel ran inside others' naming
//! them — and on each binding what it carried
//! (`200×200 f32 depth`). Read from `report.json`'s shape, so `gudsl render --with-report`,
//! ▶ Run pipeline and the live preview draw it alike.

use gudsl_model::graph::{Compartment, Graph};
use serde_json::Value;

/// `graph` (the diagram `report` ran) with the report's times and flows on it; an error when
/// the report is of another diagram or is no pipeline's report.
pub fn annotate(graph: &mut Graph, report: &Value) -> Result<(), String> {
    let diagram = report["diagram"].as_str().ok_or("it is no pipeline's report.json (no `diagram`)")?;
    if diagram != graph.id {
        return Err(format!("it is a report of `{diagram}`, not of `{}`", graph.id));
    }
    let stages = report["stages"].as_array().ok_or("it is no pipeline's report.json (no `stages`)")?;
    let ms = |stage: &Value, key: &str| stage[key].as_f64().unwrap_or(0.0);
    // A stage's time per frame, host and GPU.
    let cost = |stage: &Value| ms(stage, "host_ms_per_frame") + ms(stage, "device_ms_per_frame");
    let total: f64 = stages.iter().map(cost).sum();
    let slowest = stages.iter().max_by(|a, b| cost(a).total_cmp(&cost(b))).and_then(|s| s["instance"].as_str());
    for stage in stages {
        let Some(node) = graph.nodes.iter_mut().find(|n| Some(n.id.as_str()) == stage["instance"].as_str()) else {
            continue;
        };
        let share = cost(stage) / total.max(1e-12) * 100.0;
        let inside: Vec<&str> =
            stage["fused_into"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
        let line = match stage["replayed"].as_bool() == Some(true) {
            true => "replayed (unchanged)".to_string(),
            false => {
                let device = ms(stage, "device_ms_per_frame");
                let time = format!("{:.2} ms/frame (GPU {device:.2}) · {share:.0} %", cost(stage));
                match inside.as_slice() {
                    [] => time,
                    inside => format!("{time} · {}", super::report::runs_in(inside)),
                }
            }
        };
        node.compartments.push(Compartment::plain(None, vec![line]));
        if stage["state"] == "failed" {
            node.stereotype = Some("failed".to_string());
        } else if Some(node.id.as_str()) == slowest && total > 0.0 {
            node.stereotype = Some("slowest".to_string());
        }
    }
    for flow in report["bindings"].as_array().into_iter().flatten() {
        let Some(carries) = flow["carries"].as_str() else { continue };
        // A graph's port is `instance.portInstance.connector`.
        let port = |instance: &str, port: &str| Some(format!("{}.{}", flow[instance].as_str()?, flow[port].as_str()?));
        let (from, to) = (port("provider", "provider_port"), port("processor", "processor_port"));
        for edge in graph.edges.iter_mut().filter(|e| from.is_some() && e.source.port == from && e.target.port == to) {
            edge.label = Some(match edge.label.take() {
                Some(name) => format!("{name}: {carries}"),
                None => carries.to_string(),
            });
        }
    }
    Ok(())
}
