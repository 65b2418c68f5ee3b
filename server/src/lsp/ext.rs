//! gudsl's own protocol beside LSP (`docs/protocol.md`; rust-analyzer's `lsp/ext.rs`): the
//! `gudsl.*` commands, and the requests, notifications and their types — `gudsl/diagrams`,
//! `gudsl/graph`, `gudsl/applyGraphEdit`, `gudsl/viewFileText`, `gudsl/graphChanged` and
//! `gudsl/preview`. The client's side is `vscode-extension/src/protocol.ts`; a test fails when
//! this file changes and the hash that `docs/protocol.md` records for it does not.

use gudsl_model::ide::Properties;
use gudsl_render::scene::Rect;
use serde::{Deserialize, Deserializer, Serialize};
use tower_lsp_server::ls_types as lsp;

/// Runs a host activity diagram: its name (simple or fully qualified), or
/// `{"diagram": name, "output": folder}`.
pub const RUN: &str = "gudsl.run";

/// Runs a pipeline: its name (simple or fully qualified), or
/// `{"diagram": name, "output": folder, "frames": n, "cpu": bool}`.
pub const RUN_PIPELINE: &str = "gudsl.runPipeline";

/// Answers with the generated WGSL of a diagram (its name, simple or fully qualified, or
/// `{"diagram": name}`), or of every device diagram of a document (`{"uri": uri}`).
pub const SHOW_WGSL: &str = "gudsl.showWgsl";

/// Turns a pipeline's live preview on or off: its name (toggles), or `{"diagram": name,
/// "live": bool, "frames": n, "cpu": bool}`; answered with [`PreviewState`]. While it is live,
/// `gudsl/preview` brings its results.
pub const PREVIEW: &str = "gudsl.preview";

/// The commands `workspace/executeCommand` takes.
pub const COMMANDS: [&str; 4] = [RUN, RUN_PIPELINE, SHOW_WGSL, PREVIEW];

/// The requests beyond LSP a client may send.
pub const REQUESTS: [&str; 6] = [
    "gudsl/diagrams",
    "gudsl/graph",
    "gudsl/applyGraphEdit",
    "gudsl/viewFileText",
    "gudsl/parameters",
    "gudsl/setParameter",
];

/// The notifications beyond LSP a client may get.
pub const NOTIFICATIONS: [&str; 2] = [GraphChangedNotification::METHOD_NAME, PreviewNotification::METHOD_NAME];

// ---- gudsl.preview, gudsl/preview

/// The answer of `gudsl.preview`: which pipeline is live now, if one is.
#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct PreviewState {
    /// The live pipeline (fully qualified), `null` when none is.
    pub diagram: Option<String>,
    pub live: bool,
    /// The frames each preview runs (the first ones).
    pub frames: usize,
}

/// `gudsl/preview`: a live preview ran, or stopped (the model has errors; it goes on once they
/// are fixed). Previews are numbered: an older one never follows a newer.
#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Preview {
    pub diagram: String,
    /// The document that declares it, and the version previewed.
    pub uri: Option<lsp::Uri>,
    pub version: Option<i32>,
    pub sequence: u64,
    /// `ran`, `failed` (it ran and stopped with an error), or `stopped` (the model has errors:
    /// nothing ran).
    pub state: String,
    /// One line: what it ran, in how long, or why it stopped.
    pub message: String,
    /// The run's report, as `report.json` has it (stages' times, figures, outputs).
    pub report: Option<serde_json::Value>,
    /// The stages that gave what they gave in the last preview instead of running again.
    pub replayed: Vec<String>,
    /// Where the model's errors are (`stopped`) or where the run stopped (`failed`): each
    /// `{uri, range, code, message}`.
    pub problems: Vec<serde_json::Value>,
    /// The folder its outputs are in.
    pub output: Option<String>,
    pub timings: PreviewTimings,
}

/// Where a preview's time went, in milliseconds from the edit the server received.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct PreviewTimings {
    /// Checking the model and preparing the pipeline.
    pub prepare_ms: f64,
    /// Waiting for the preview thread (a preview under way finishing its stage).
    pub queued_ms: f64,
    /// Running the frames.
    pub run_ms: f64,
    /// From the edit to the notification sent.
    pub total_ms: f64,
}

pub enum PreviewNotification {}

impl PreviewNotification {
    const METHOD_NAME: &'static str = "gudsl/preview";
}

impl lsp::notification::Notification for PreviewNotification {
    type Params = Preview;
    const METHOD: &'static str = Self::METHOD_NAME;
}

// ---- gudsl/parameters, gudsl/setParameter

/// An instance of a pipeline, by document, diagram (fully qualified) and instance name.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ParametersParams {
    pub text_document: lsp::TextDocumentIdentifier,
    pub diagram: String,
    pub instance: String,
}

/// `gudsl/parameters`: what a parameter panel shows of an instance.
#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Parameters {
    pub uri: lsp::Uri,
    /// The document version they describe (what `gudsl/setParameter` names).
    pub version: Option<i32>,
    pub instance: String,
    /// Its component, fully qualified.
    pub component: String,
    pub parameters: Vec<ParameterView>,
}

/// One parameter: its declared type and constraints, and its value.
#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ParameterView {
    pub name: String,
    /// The field's type as declared: `int`, `float`, `bool`, `string`, or an enum's name.
    #[serde(rename = "type")]
    pub ty: String,
    /// The value as a model writes it (`5`, `0.5`, `true`, `"a.npy"`, `Scene.Sphere`); `null`
    /// when it has none.
    pub value: Option<String>,
    /// Whether the instance writes it (else it is the field's default).
    pub written: bool,
    /// Its `ToF.Range`.
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// A slider's step: 1 for an integer, 2 for an odd one; `null` for a float.
    pub step: Option<f64>,
    /// An enum's members, as a model writes them.
    pub choices: Vec<String>,
    /// It names a file to read.
    pub input_file: bool,
}

/// `gudsl/setParameter`: the edit that sets an instance's parameter, for the client to apply.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct SetParameterParams {
    /// The document at the version the panel shows (another version is refused).
    pub text_document: lsp::OptionalVersionedTextDocumentIdentifier,
    pub diagram: String,
    pub instance: String,
    pub parameter: String,
    /// As a model writes it.
    pub value: String,
}

// ---- gudsl/diagrams, gudsl/graph

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct DiagramsParams {
    pub text_document: lsp::TextDocumentIdentifier,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Diagrams {
    pub uri: lsp::Uri,
    /// The document version the list describes (`null` for a file the editor has not open).
    pub version: Option<i32>,
    pub diagrams: Vec<DiagramInfo>,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DiagramInfo {
    /// The diagram's fully qualified name: what `gudsl/graph` takes.
    pub id: String,
    pub name: String,
    pub kind: String,
    /// The whole declaration, and its name (where to put the cursor).
    pub range: lsp::Range,
    pub selection_range: lsp::Range,
}

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphParams {
    pub text_document: lsp::TextDocumentIdentifier,
    /// A diagram's id, as `gudsl/diagrams` lists it.
    pub diagram: String,
    /// Whether to add the SVG of the scene.
    #[serde(default)]
    pub svg: bool,
    /// Whether to add the scene as a PNG (base64, drawn at twice its size), as `gudsl render
    /// --format png` writes it.
    #[serde(default)]
    pub png: bool,
    /// Whether to lay the nodes no pin holds out afresh, instead of around the scene drawn
    /// before (where an edit leaves them).
    #[serde(default)]
    pub relayout: bool,
    /// The size of the client's diagram view, in px: a fresh layout that does not fit it is
    /// fitted to its shape (`docs/render.md`, "Fitting the page"). Kept for the diagram's later
    /// layouts; without one, the last given, else a 16:10 screen.
    #[serde(default)]
    pub page: Option<PageSize>,
}

#[derive(Debug, Deserialize)]
pub struct PageSize {
    pub width: f64,
    pub height: f64,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphView {
    pub uri: lsp::Uri,
    pub version: Option<i32>,
    pub diagram: DiagramInfo,
    /// The scene's size; coordinates are in points, x to the right, y down.
    pub width: f64,
    pub height: f64,
    pub nodes: Vec<NodeView>,
    pub edges: Vec<EdgeView>,
    pub groups: Vec<GroupView>,
    /// The decision and merge diamonds the drawing adds where an activity's text leaves them
    /// implicit; the routes of the transitions through them pass their centres.
    pub controls: Vec<ControlView>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub svg: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub png: Option<String>,
    /// Why the document's layout sidecar was not used (it is not valid): the sidecar's path and
    /// the reason.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layout_error: Option<String>,
}

/// A decision (branches leave it) or merge (flows meet at it) drawn before or after a node.
#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ControlView {
    pub id: String,
    /// `decision` or `merge`.
    pub kind: String,
    /// The node it belongs to: the one whose flows branch, or meet.
    pub node: String,
    pub bounds: Bounds,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct NodeView {
    pub id: String,
    pub shape: String,
    pub label: String,
    pub stereotype: Option<String>,
    pub is_abstract: bool,
    pub compartments: Vec<CompartmentView>,
    pub ports: Vec<PortView>,
    pub group: Option<String>,
    /// The node it is drawn inside (a nested component's parent).
    pub parent: Option<String>,
    pub range: lsp::Range,
    pub bounds: Option<Bounds>,
    /// Whether the user put it where it is (`move`): the layout sidecar holds it there.
    pub pinned: bool,
}

#[derive(Debug, Serialize)]
pub struct CompartmentView {
    pub title: Option<String>,
    pub lines: Vec<String>,
    /// The id of the element each line shows (a field, a method, …), `""` for a plain line.
    pub ids: Vec<String>,
    /// Whether each line shows a static (`global`) member: UML underlines it.
    pub statics: Vec<bool>,
}

#[derive(Debug, Serialize)]
pub struct PortView {
    pub id: String,
    pub label: String,
    /// `true` a provider (lollipop), `false` a processor (socket), `null` a port instance.
    pub provider: Option<bool>,
    /// Where connections meet it (just outside its symbol, right of the node's box).
    pub anchor: Option<Point>,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct EdgeView {
    pub id: String,
    pub kind: String,
    pub source: EndView,
    pub target: EndView,
    pub label: Option<String>,
    pub source_label: Option<String>,
    pub target_label: Option<String>,
    /// The text that states it.
    pub range: lsp::Range,
    /// The route, source to target; empty where an end is not in the diagram.
    pub points: Vec<Point>,
    /// The box of the label along it, and of the labels at its source and target end.
    pub label_bounds: Option<Bounds>,
    pub source_label_bounds: Option<Bounds>,
    pub target_label_bounds: Option<Bounds>,
}

#[derive(Debug, Serialize)]
pub struct EndView {
    pub node: String,
    pub port: Option<String>,
}

#[derive(Debug, Serialize)]
pub struct GroupView {
    pub id: String,
    pub label: String,
    pub owner: Option<String>,
    pub bounds: Option<Bounds>,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Bounds {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Point {
    pub x: f64,
    pub y: f64,
}

impl From<Rect> for Bounds {
    fn from(r: Rect) -> Bounds {
        Bounds { x: r.x, y: r.y, width: r.width, height: r.height }
    }
}

// ---- gudsl/applyGraphEdit

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphEditParams {
    /// The document and the version the client's graph describes: an edit against another
    /// version is refused.
    pub text_document: lsp::OptionalVersionedTextDocumentIdentifier,
    pub diagram: String,
    pub operations: Vec<Operation>,
}

/// One operation of `gudsl/applyGraphEdit`, named by `op`.
#[derive(Debug, Deserialize)]
#[serde(tag = "op", rename_all = "camelCase")]
pub enum Operation {
    /// A new node, member, port, connector or port instance (`kind`: `class`, `field`, `action`,
    /// `loopWindow`, `portInstance`, …), into `parent` (a class, swimlane, component, instance).
    #[serde(rename_all = "camelCase")]
    Create {
        kind: String,
        name: String,
        parent: Option<String>,
        #[serde(default)]
        properties: Properties,
    },
    /// An element and what dangles without it.
    Delete { element: String },
    /// A node and every reference to it, across files.
    Rename { element: String, name: String },
    /// A new edge (`kind`: `transition`, `generalization`, `realization`, `association`,
    /// `aggregation`, `composition`, `connection`, `binding`).
    Connect {
        kind: String,
        source: String,
        target: String,
        #[serde(default)]
        properties: Properties,
    },
    /// An edge's new source or target.
    Reconnect { edge: String, source: Option<String>, target: Option<String> },
    /// A property's new value; `null` removes it.
    #[serde(rename_all = "camelCase")]
    SetProperty { element: String, property: String, value: Option<String> },
    /// Pins a node with its top-left corner at `position`; `null` unpins it.
    Move {
        element: String,
        #[serde(default, deserialize_with = "given")]
        position: Option<Option<Position>>,
    },
    /// Gives a node `size` (it is never drawn smaller than its text); `null` its own size again.
    Resize {
        element: String,
        #[serde(default, deserialize_with = "given")]
        size: Option<Option<Size>>,
    },
}

/// A field that may be `null` but must be there: `Some(None)` for `null`, `None` if missing.
fn given<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<Option<T>>, D::Error> {
    Option::<T>::deserialize(d).map(Some)
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub struct Position {
    pub x: f64,
    pub y: f64,
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub struct Size {
    pub width: f64,
    pub height: f64,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphEditAnswer {
    /// The text edits that make the operations, for the client to apply.
    pub edit: lsp::WorkspaceEdit,
    /// The layout sidecar written for `move` and `resize` (already on disk).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layout: Option<LayoutWritten>,
}

#[derive(Debug, Serialize)]
pub struct LayoutWritten {
    /// The sidecar (`file:///…/model.gudsl.layout`).
    pub uri: lsp::Uri,
    /// The diagram whose positions changed.
    pub diagram: String,
}

// ---- gudsl/graphChanged

/// `gudsl/graphChanged`: diagrams a client fetched changed (an edit of the text, or of the
/// positions, which publishes no diagnostics): ask for them again.
#[derive(Debug, Serialize, Deserialize)]
pub struct GraphChanged {
    pub uri: lsp::Uri,
    pub version: Option<i32>,
    pub diagrams: Vec<String>,
}

pub enum GraphChangedNotification {}

impl GraphChangedNotification {
    const METHOD_NAME: &'static str = "gudsl/graphChanged";
}

impl lsp::notification::Notification for GraphChangedNotification {
    type Params = GraphChanged;
    const METHOD: &'static str = Self::METHOD_NAME;
}
