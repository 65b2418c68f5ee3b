//! The generated device code in the editor (what cannot be generated is a diagnostic, E0301,
//! decided with the others in `gudsl_host::diagnostics`): the WGSL of a device diagram is a read-only document,
//! `gudsl:/wgsl/<diagram>.wgsl`, that `gudsl.showWgsl` names and `gudsl/viewFileText` serves
//! (regenerated from the current model each time it is read).

use gudsl_host::named::names_diagram;
use gudsl_model::{
    hir::{DefKind, Definition, Semantics},
    Cancellable, FileId,
};
use serde_json::{json, Value};

use super::{ext::SHOW_WGSL, host::Snapshot, to_proto};

/// The scheme and folder of the generated documents' URIs.
const PREFIX: &str = "gudsl:/wgsl/";

/// The kernels declared in `file` (only its own activity diagrams are looked at: this runs for
/// every file whose diagnostics are computed).
fn device_diagrams_of<'db>(sema: &Semantics<'db>, file: FileId) -> Vec<&'db Definition> {
    sema.file_diagrams(file)
        .filter(|def| matches!(def.kind, DefKind::Activity(_)))
        .filter(|def| gudsl_codegen::is_kernel(sema, def))
        .collect()
}

/// The URI of a device diagram's generated WGSL.
pub fn document_uri(diagram: &str) -> String {
    format!("{PREFIX}{diagram}.wgsl")
}

/// The diagram a generated document's URI names, if it is one.
pub fn diagram_of(uri: &str) -> Option<&str> {
    uri.strip_prefix(PREFIX)?.strip_suffix(".wgsl")
}

/// `gudsl.showWgsl`: `{uri, languageId, text}` of the generated document, or why there is none
/// (no such device diagram, or what cannot be generated, with its place).
pub fn show(snap: &Snapshot, argument: &Value) -> Cancellable<Result<Value, String>> {
    let wanted = match argument {
        Value::String(name) => Wanted::Diagram(name.clone()),
        Value::Object(fields) => match (fields.get("diagram"), fields.get("uri")) {
            (Some(Value::String(name)), _) => Wanted::Diagram(name.clone()),
            (None, Some(Value::String(uri))) => match uri.parse().ok().and_then(|uri| snap.file(&uri)) {
                Some(file) => Wanted::File(file, uri.clone()),
                None => return Ok(Err(format!("{uri} is not a document of the workspace"))),
            },
            _ => return Ok(Err(argument_error())),
        },
        _ => return Ok(Err(argument_error())),
    };
    let (uri, text) = match &wanted {
        Wanted::Diagram(name) => match generated(snap, name)? {
            Ok(text) => (document_uri(name), text),
            Err(why) => return Ok(Err(why)),
        },
        Wanted::File(file, uri) => {
            let texts = snap.analysis.with_semantics(|sema| {
                let mut diagrams = device_diagrams_of(sema, *file);
                diagrams.sort_by(|a, b| a.fqn.cmp(&b.fqn));
                diagrams.into_iter().map(|def| wgsl_of(snap, sema, def)).collect::<Result<Vec<String>, String>>()
            })?;
            let text = match texts {
                Ok(texts) if texts.is_empty() => {
                    return Ok(Err(format!(
                        "{uri} declares no device diagram (an activity diagram owned by an OpenCL class)"
                    )))
                }
                Ok(texts) => texts.concat(),
                Err(why) => return Ok(Err(why)),
            };
            let stem = uri.rsplit('/').next().unwrap_or("document").trim_end_matches(".gudsl").to_string();
            (document_uri(&stem), text)
        }
    };
    Ok(Ok(json!({ "uri": uri, "languageId": "wgsl", "text": text })))
}

enum Wanted {
    Diagram(String),
    File(FileId, String),
}

fn argument_error() -> String {
    format!("{SHOW_WGSL} takes a diagram's name, {{\"diagram\": name}} or {{\"uri\": document}}")
}

/// The WGSL generated from the device diagram named `name` (simple or fully qualified name), or
/// why there is none.
pub fn generated(snap: &Snapshot, name: &str) -> Cancellable<Result<String, String>> {
    snap.analysis.with_semantics(|sema| {
        let named: Vec<&Definition> =
            gudsl_codegen::device_diagrams(sema).into_iter().filter(|def| names_diagram(name, &def.fqn)).collect();
        match named[..] {
            [def] => wgsl_of(snap, sema, def),
            [] => Err(format!("no device diagram named `{name}` (an activity diagram owned by an OpenCL class)")),
            _ => Err(format!(
                "several device diagrams are named `{name}`: {}; name one fully qualified",
                named.iter().map(|def| def.fqn.as_str()).collect::<Vec<_>>().join(", ")
            )),
        }
    })
}

/// The WGSL generated from the device diagram `def`, or its first problem with its place.
fn wgsl_of(snap: &Snapshot, sema: &Semantics<'_>, def: &Definition) -> Result<String, String> {
    gudsl_codegen::generate(sema, def).map(|kernel| kernel.wgsl).map_err(|errors| {
        let first = &errors[0];
        let index = gudsl_model::db::line_index(sema.db(), first.file);
        let place = to_proto::place(first.file.path(sema.db()), index, first.range, snap.encoding);
        format!("`{}` cannot be generated ({} problem(s)); first: {place}: {}", def.fqn, errors.len(), first.message)
    })
}
