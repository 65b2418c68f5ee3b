//! Layout-JSON writer: a scene's geometry as the neutral JSON `research/layout_metrics.py`
//! scores (node boxes, edge polylines, label boxes; x, y = top-left), so layouts can be compared
//! with dot's, ELK's and others'.

use crate::{scene::Scene, svg::f};

fn string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The JSON document of a scene's geometry.
pub fn write(scene: &Scene) -> String {
    let nodes: Vec<String> = scene
        .nodes
        .iter()
        .map(|n| {
            let r = n.rect;
            format!(
                r#"{{"id":{},"x":{},"y":{},"w":{},"h":{}}}"#,
                string(&n.id),
                f(r.x),
                f(r.y),
                f(r.width),
                f(r.height)
            )
        })
        .collect();
    let mut edges = Vec::new();
    let mut labels = Vec::new();
    for (i, edge) in scene.edges.iter().enumerate() {
        let points: Vec<String> = edge.points.iter().map(|p| format!("[{},{}]", f(p.x), f(p.y))).collect();
        edges.push(format!(
            r#"{{"src":{},"dst":{},"points":[{}]}}"#,
            string(&edge.source),
            string(&edge.target),
            points.join(",")
        ));
        if let Some(label) = &edge.label {
            let r = label.rect;
            labels.push(format!(
                r#"{{"edge":{i},"kind":"mid","x":{},"y":{},"w":{},"h":{}}}"#,
                f(r.x),
                f(r.y),
                f(r.width),
                f(r.height)
            ));
        }
    }
    format!("{{\"nodes\":[{}],\"edges\":[{}],\"labels\":[{}]}}\n", nodes.join(","), edges.join(","), labels.join(","))
}
