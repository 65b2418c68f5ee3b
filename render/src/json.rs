//! Layout-JSON writer: a scene's geometry as the neutral JSON `research/layout_metrics.py`
//! scores (node boxes, edge polylines, label boxes; x, y = top-left), so layouts can be compared
//! with dot's, ELK's and others'. Each edge also has its kind and each label its kind (`mid`,
//! `tail`, `head`) and text, so another layout tool can be given the same edges and labels.

use crate::{scene::Scene, svg::f};

fn string(s: &str) -> String {
    serde_json::Value::from(s).to_string()
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
            r#"{{"src":{},"dst":{},"kind":{},"points":[{}]}}"#,
            string(&edge.source),
            string(&edge.target),
            string(edge.kind.name()),
            points.join(",")
        ));
        for (kind, label) in [("mid", &edge.label), ("tail", &edge.tail_label), ("head", &edge.head_label)] {
            let Some(label) = label else { continue };
            let r = label.rect;
            let text: Vec<&str> = label.lines.iter().map(|(_, line)| line.as_str()).collect();
            labels.push(format!(
                r#"{{"edge":{i},"kind":"{kind}","text":{},"x":{},"y":{},"w":{},"h":{}}}"#,
                string(&text.join("\n")),
                f(r.x),
                f(r.y),
                f(r.width),
                f(r.height)
            ));
        }
    }
    format!("{{\"nodes\":[{}],\"edges\":[{}],\"labels\":[{}]}}\n", nodes.join(","), edges.join(","), labels.join(","))
}
