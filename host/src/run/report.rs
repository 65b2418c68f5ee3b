//! What a host run did, for people and scripts: its one-line summary and `report.json`, which
//! `gudsl run` and the editor's ▶ Run write alike.

use std::time::Duration;

use super::{Ending, Report, RunErrorKind};
use crate::output::OutputDir;

/// One line: how the run ended, in how long, on which device.
pub fn summary(report: &Report) -> String {
    let ended = match &report.outcome {
        Ok(Ending::Final(node)) => format!("ran {} to final node `{node}`", report.diagram),
        Ok(Ending::NoTransition(node)) => {
            format!("ran {} until `{node}`, which has no transition whose guard holds", report.diagram)
        }
        Err(error) if error.kind == RunErrorKind::Cancelled => format!("{}: {error}", report.diagram),
        Err(_) => format!("{} stopped with an error", report.diagram),
    };
    format!(
        "{ended} in {} ({} nodes; kernels compiled in {}) on {}",
        ms(report.total),
        report.nodes_run,
        ms(report.compile),
        report.device
    )
}

fn ms(duration: Duration) -> String {
    format!("{:.1} ms", duration.as_secs_f64() * 1000.0)
}

/// Writes `report.json` into `output`; the report as written.
pub fn write_report(report: &Report, output: &mut OutputDir) -> Result<serde_json::Value, String> {
    let json = report_json(report);
    let text = serde_json::to_string_pretty(&json).expect("a report serialises");
    output.write_top("report.json", (text + "\n").as_bytes())?;
    Ok(json)
}

/// `report.json`: what the run did, for scripts.
fn report_json(report: &Report) -> serde_json::Value {
    let millis = |d: Duration| d.as_secs_f64() * 1000.0;
    let (ended_at, error) = match &report.outcome {
        Ok(Ending::Final(node)) | Ok(Ending::NoTransition(node)) => (Some(node.clone()), None),
        Err(error) => (None, Some(error.message.clone())),
    };
    serde_json::json!({
        "diagram": report.diagram,
        "device": report.device,
        "ended_at": ended_at,
        "reached_final_node": matches!(report.outcome, Ok(Ending::Final(_))),
        "error": error,
        "nodes_run": report.nodes_run,
        "compile_ms": millis(report.compile),
        "total_ms": millis(report.total),
        "nodes": report.nodes.iter().map(|n| serde_json::json!({
            "name": n.name, "runs": n.runs, "wall_ms": millis(n.wall),
        })).collect::<Vec<_>>(),
        "calcs": report.calcs.iter().map(|c| serde_json::json!({
            "node": c.node, "kernel": c.kernel, "launches": c.launches,
            "device_ms": millis(c.device), "wall_ms": millis(c.wall),
        })).collect::<Vec<_>>(),
        "images": report.images.iter().map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned())).collect::<Vec<_>>(),
        "printed": report.printed,
    })
}
