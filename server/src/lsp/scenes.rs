//! The scenes the server has drawn, by document and diagram: asked for again with nothing drawn
//! changed, a diagram is not laid out again; changed, it is laid out around the scene drawn
//! before (its nodes stay where they were) and the nodes pinned in the document's layout
//! sidecar. The same memory says which diagrams a client has fetched that an edit changed
//! (`gudsl/graphChanged`), in any document. A pipeline is drawn with the times and flows of
//! its last run or live preview on it (`gudsl_host::pipeline::annotate`).

use std::{
    collections::HashMap,
    sync::{Arc, Mutex},
};

use gudsl_model::{graph::Graph, syntax::TextRange, Cancellable, FileId};
use gudsl_render::{
    layout::Page,
    pins::{LayoutFile, Pins, Rows},
    scene::{self, Hints, Scene},
};
use tower_lsp_server::ls_types as lsp;

use super::{ext::GraphChanged, host::Snapshot};
use crate::layout_file;

/// The scenes last laid out, and the last report of each pipeline run.
#[derive(Default)]
pub struct SceneCache(Mutex<Scenes>, Mutex<HashMap<String, serde_json::Value>>);

/// By document and diagram id: what was drawn.
type Scenes = HashMap<(FileId, String), Drawn>;

struct Drawn {
    /// The graph, its source ranges cleared (an edit above a diagram moves only those).
    graph: Graph,
    pins: Option<Pins>,
    scene: Arc<Scene>,
    /// The page its fresh layouts are fitted to, once a client told one (else a screen's).
    page: Option<Page>,
}

/// Diagrams whose scenes are kept; past it the cache starts again.
const CACHED_SCENES: usize = 64;

impl SceneCache {
    /// The scene of `graph` with `pins`: the one kept if nothing drawn changed, else laid out
    /// around the one kept (or afresh, `relayout`, for the nodes no pin holds); a fresh layout
    /// fitted to `page` (none: the page told before, else a screen's) and keeping the rows of
    /// the one kept, else the sidecar's `rows` (a re-layout only those).
    pub fn scene(
        &self,
        file: FileId,
        graph: &Graph,
        (pins, rows): (Option<&Pins>, Option<&Rows>),
        relayout: bool,
        page: Option<Page>,
    ) -> Arc<Scene> {
        let drawn = without_ranges(graph);
        let key = (file, graph.id.clone());
        let kept =
            self.lock().get(&key).map(|d| (d.graph == drawn && d.pins.as_ref() == pins, d.scene.clone(), d.page));
        // A page is kept for later layouts. The first one told lays the diagram out afresh
        // (a client may ask before it knows its size); after that it matters only to a fresh
        // layout, so a scene whose drawing did not change is kept as it is.
        let first_told = page.is_some() && kept.as_ref().is_some_and(|k| k.2.is_none());
        let page = page.or(kept.as_ref().and_then(|k| k.2));
        let kept_rows = kept.as_ref().map(|k| k.1.clone());
        let previous = match kept {
            Some((true, scene, _)) if !relayout && !first_told => {
                self.lock().entry(key).and_modify(|d| d.page = page);
                return scene;
            }
            Some((_, scene, _)) if !relayout && !first_told => Some(scene),
            _ => None,
        };
        // A re-layout keeps the rows saved with the model (deleted there, it starts afresh);
        // any other fresh layout those of the scene kept, else the saved ones.
        let rows = if relayout { rows } else { kept_rows.as_ref().map(|scene| &scene.rows).or(rows) };
        let hints = Hints { pins, previous: previous.as_deref(), page: page.unwrap_or_default(), rows };
        let scene = Arc::new(scene::build(graph, hints));
        let mut scenes = self.lock();
        if scenes.len() >= CACHED_SCENES {
            scenes.clear();
        }
        scenes.insert(key, Drawn { graph: drawn, pins: pins.cloned(), scene: scene.clone(), page });
        scene
    }

    /// The rows of each diagram of `file` drawn (what its next fresh layout keeps), by diagram.
    pub fn rows_of(&self, file: FileId) -> Vec<(String, Rows)> {
        let scenes = self.lock();
        let mut rows: Vec<(String, Rows)> = scenes
            .iter()
            .filter(|(key, _)| key.0 == file)
            .map(|(key, d)| (key.1.clone(), d.scene.rows.clone()))
            .collect();
        rows.sort();
        rows
    }

    /// The diagrams drawn for a client whose graph is no longer what was drawn (or that are
    /// gone), by document: an edit can change a diagram of another document (a class diagram
    /// draws the types its edges reach).
    pub fn changed(&self, snap: &Snapshot) -> Cancellable<Vec<GraphChanged>> {
        let drawn: Vec<(FileId, String, Graph)> =
            self.lock().iter().map(|(k, d)| (k.0, k.1.clone(), d.graph.clone())).collect();
        let mut drawn: Vec<(lsp::Uri, FileId, String, Graph)> =
            drawn.into_iter().filter_map(|(file, id, graph)| Some((snap.uri_of(file)?, file, id, graph))).collect();
        drawn.sort_by(|a, b| (a.0.as_str(), &a.2).cmp(&(b.0.as_str(), &b.2)));
        let mut changed: Vec<GraphChanged> = Vec::new();
        for (uri, file, id, was) in drawn {
            let graphs = snap.analysis.graphs(file)?;
            if graphs.iter().find(|g| g.id == id).is_some_and(|g| without_ranges(&self.as_drawn(g)) == was) {
                continue;
            }
            match changed.last_mut() {
                Some(last) if last.uri == uri => last.diagrams.push(id),
                _ => {
                    let version = snap.document(&uri).and_then(|d| d.version);
                    changed.push(GraphChanged { uri, version, diagrams: vec![id] });
                }
            }
        }
        Ok(changed)
    }

    /// Keeps `report` (a pipeline run's `report.json`) to draw on its diagram from now on;
    /// `gudsl/graphChanged` for each document where a client fetched that diagram.
    pub fn ran(&self, report: &serde_json::Value, snap: &Snapshot) -> Vec<GraphChanged> {
        let Some(diagram) = report["diagram"].as_str() else { return Vec::new() };
        let mut reports = self.1.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        reports.insert(diagram.to_string(), report.clone());
        drop(reports);
        let files: Vec<FileId> = self.lock().keys().filter(|(_, id)| id == diagram).map(|(file, _)| *file).collect();
        let changed = files.into_iter().filter_map(|file| snap.uri_of(file)).map(|uri| {
            let version = snap.document(&uri).and_then(|d| d.version);
            GraphChanged { uri, version, diagrams: vec![diagram.to_string()] }
        });
        changed.collect()
    }

    /// `graph` as it is drawn: a pipeline with its last run's report on it (what
    /// [`SceneCache::scene`] is given).
    pub fn as_drawn<'g>(&self, graph: &'g Graph) -> std::borrow::Cow<'g, Graph> {
        let reports = self.1.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let Some(report) = reports.get(&graph.id) else { return std::borrow::Cow::Borrowed(graph) };
        let mut annotated = graph.clone();
        match gudsl_host::pipeline::annotate(&mut annotated, report) {
            Ok(()) => std::borrow::Cow::Owned(annotated),
            Err(_) => std::borrow::Cow::Borrowed(graph),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Scenes> {
        self.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// `graph` as drawn: its source ranges cleared.
fn without_ranges(graph: &Graph) -> Graph {
    let mut drawn = graph.clone();
    (drawn.range, drawn.name_range) = (TextRange::default(), None);
    for node in &mut drawn.nodes {
        node.range = TextRange::default();
    }
    for edge in &mut drawn.edges {
        edge.range = TextRange::default();
    }
    drawn
}

/// The layout sidecar of a document: none for a document that is no file (`untitled:`);
/// `Err` names the sidecar and says why it is no layout.
pub fn layout_of(uri: &lsp::Uri) -> Result<LayoutFile, String> {
    match super::from_proto::file_path(uri) {
        Some(path) => layout_file::read(&layout_file::path_for(&path)),
        None => Ok(LayoutFile::default()),
    }
}

#[cfg(test)]
mod tests {
    use gudsl_model::AnalysisHost;
    use gudsl_render::pins::Pin;

    use super::*;

    const TEXT: &str =
        "ClassDiagram Shapes\n{\n    public class Shape { }\n    public class Circle extends Shape { }\n}\n";

    #[test]
    fn a_scene_is_laid_out_again_only_when_what_is_drawn_changes() {
        let (mut host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), TEXT.to_string())]);
        let cache = SceneCache::default();
        let scene = |host: &AnalysisHost, pins: Option<&Pins>| {
            cache.scene(files[0], &host.analysis().graphs(files[0]).unwrap()[0], (pins, None), false, None)
        };
        let first = scene(&host, None);
        // Text above the diagram moves its ranges, not what is drawn.
        host.set_file_text(files[0], format!("// shapes\n\n{TEXT}"));
        assert!(Arc::ptr_eq(&first, &scene(&host, None)), "laid out again for a comment");
        let grown = TEXT
            .replace("    public class Circle", "    public class Square extends Shape { }\n    public class Circle");
        host.set_file_text(files[0], grown);
        let second = scene(&host, None);
        assert!(!Arc::ptr_eq(&first, &second));
        assert_eq!(second.nodes.len(), 3);
        // The nodes drawn before stay where they were.
        for node in &first.nodes {
            assert_eq!(second.nodes.iter().find(|n| n.id == node.id).unwrap().rect, node.rect);
        }
        // A pin is a change of what is drawn.
        let mut pins = Pins::new();
        pins.insert("Shapes.Shape".into(), Pin { x: 400.0, y: 300.0, width: None, height: None });
        let pinned = scene(&host, Some(&pins));
        let shape = pinned.nodes.iter().find(|n| n.id == "Shapes.Shape").unwrap().rect;
        assert_eq!((shape.x, shape.y), (400.0, 300.0));
        assert!(Arc::ptr_eq(&pinned, &scene(&host, Some(&pins))));
    }

    #[test]
    fn a_relayout_keeps_the_saved_rows_and_without_them_starts_afresh() {
        let grown = TEXT
            .replace("    public class Circle", "    public class Square extends Shape { }\n    public class Circle");
        let (host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), grown)]);
        let graph = &host.analysis().graphs(files[0]).unwrap()[0].clone();
        let cache = SceneCache::default();
        let first = cache.scene(files[0], graph, (None, None), false, None);
        // Saved rows with the children the other way round: a re-layout keeps them.
        let x = |scene: &Scene, id: &str| scene.nodes.iter().find(|n| n.id == id).unwrap().rect.x;
        let mut children = ["Shapes.Circle", "Shapes.Square"];
        children.sort_by(|a, b| x(&first, b).total_cmp(&x(&first, a)));
        let saved: Rows = vec![vec!["Shapes.Shape".into()], children.iter().map(|c| c.to_string()).collect()];
        let kept = cache.scene(files[0], graph, (None, Some(&saved)), true, None);
        assert!(x(&kept, children[0]) < x(&kept, children[1]));
        // Without saved rows, a re-layout is the layout afresh, whatever the session drew.
        let afresh = cache.scene(files[0], graph, (None, None), true, None);
        assert_eq!(*afresh, scene::build(graph, Hints::default()));
    }
}
