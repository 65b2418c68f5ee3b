//! A pipeline instance's parameters for an editor's controls (`gudsl/parameters`: each with
//! its declared type, range, oddness and choices, from the plan the runs use) and the edit that
//! sets one (`gudsl/setParameter`: `ide::parameter_edit`, what `gudsl run --set` writes), so a
//! slider changes the text — undoable, formatted as typed — and the live preview follows it.

use gudsl_model::{
    hir::pipeline::{Param, Value},
    Cancellable,
};
use tower_lsp_server::ls_types as lsp;

use super::{
    ext::{ParameterView, Parameters, ParametersParams, SetParameterParams},
    graph::version,
    host::Snapshot,
    to_proto,
};

/// `gudsl/parameters`; `Err` with the reason when the document, the pipeline or the instance is
/// unknown.
pub fn parameters(snap: &Snapshot, params: &ParametersParams) -> Cancellable<Result<Parameters, String>> {
    let uri = &params.text_document.uri;
    if snap.file(uri).is_none() {
        return Ok(Err(format!("{} is not a document of the workspace", uri.as_str())));
    }
    let Some(plan) = snap.analysis.pipeline_plan(&params.diagram)? else {
        return Ok(Err(format!("no component-instance diagram `{}`", params.diagram)));
    };
    let Some(stage) = plan.stages.iter().find(|s| s.instance == params.instance) else {
        let known: Vec<&str> = plan.stages.iter().map(|s| s.instance.as_str()).collect();
        return Ok(Err(format!(
            "`{}` has no instance `{}` (it has: {})",
            plan.diagram,
            params.instance,
            known.join(", ")
        )));
    };
    Ok(Ok(Parameters {
        uri: uri.clone(),
        version: version(snap, uri),
        instance: stage.instance.clone(),
        component: stage.class.clone(),
        parameters: stage.params.iter().map(view).collect(),
    }))
}

fn view(param: &Param) -> ParameterView {
    let control = &param.control;
    let whole = matches!(control.ty.as_str(), "int" | "unsigned" | "uint" | "long" | "short" | "char");
    ParameterView {
        name: param.name.clone(),
        ty: control.ty.clone(),
        value: written(&param.value, &control.choices),
        written: param.written.is_some(),
        min: control.range.map(|(min, _)| min.get()),
        max: control.range.map(|(_, max)| max.get()),
        step: whole.then_some(if control.odd { 2.0 } else { 1.0 }),
        choices: control.choices.clone(),
        input_file: param.input_file,
    }
}

/// A value as a model writes it; an enum member with its enum's name.
fn written(value: &Value, choices: &[String]) -> Option<String> {
    Some(match value {
        Value::Int(v) => v.to_string(),
        Value::Float(v) => v.get().to_string(),
        Value::Bool(v) => v.to_string(),
        Value::Text(text) => format!("{text:?}"),
        Value::Enum(member) => {
            let qualified = choices.iter().find(|c| c.rsplit('.').next() == Some(member.as_str()));
            qualified.cloned().unwrap_or_else(|| member.clone())
        }
        Value::Missing => return None,
    })
}

/// `gudsl/setParameter`: the workspace edit that writes the value; refused for another version
/// than the server's, an unknown instance or parameter, or a value that is not one.
pub fn set_parameter(snap: &Snapshot, params: &SetParameterParams) -> Cancellable<Result<lsp::WorkspaceEdit, String>> {
    let uri = &params.text_document.uri;
    let current = version(snap, uri);
    if params.text_document.version != current {
        return Ok(Err(format!(
            "the value is for version {:?} of {}, the server has {:?}: ask for the parameters again",
            params.text_document.version,
            uri.as_str(),
            current
        )));
    }
    let edit =
        match snap.analysis.parameter_edit(&params.diagram, &params.instance, &params.parameter, &params.value)? {
            Ok(edit) => edit,
            Err(why) => return Ok(Err(why)),
        };
    if snap.uri_of(edit.file).as_ref() != Some(uri) {
        return Ok(Err(format!("`{}` is not declared in {}", params.diagram, uri.as_str())));
    }
    let range = gudsl_model::ide::FileRange { file: edit.file, range: edit.range };
    Ok(Ok(to_proto::workspace_edit(snap, vec![(range, edit.text)])?))
}
