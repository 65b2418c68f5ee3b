//! Which diagram a name means, for `gudsl run`, `gudsl wgsl`, `gudsl render` and the editor's
//! commands alike: a simple or fully qualified name, among the diagrams of the given files; a
//! name that means none or several is an error that lists those there are.

use gudsl_model::{
    hir::{DefKind, Definition, Semantics},
    FileId,
};

/// Whether `wanted` names the diagram `fqn`: its fully qualified or its simple name.
pub fn names_diagram(wanted: &str, fqn: &str) -> bool {
    wanted == fqn || fqn.rsplit('.').next() == Some(wanted)
}

/// Whether `def` is a host activity diagram without parameters (what `run` offers to run).
pub fn is_runnable(sema: &Semantics<'_>, def: &Definition) -> bool {
    matches!(&def.kind, DefKind::Activity(a) if a.params.is_empty()) && !gudsl_codegen::is_device_diagram(sema, def)
}

/// The kind of diagram a run runs, by its fully qualified name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Runnable {
    Pipeline(String),
    Activity(String),
}

/// The diagram of `files` that `name` names (simple or fully qualified), or without a name the
/// one diagram that can run: a component-instance diagram or a host activity diagram without
/// parameters; `Err` says why none is meant, listing those that can run. A name no pipeline has
/// is taken as an activity diagram's ([`activity_named`] says whether there is one).
pub fn runnable(sema: &Semantics<'_>, files: &[FileId], name: Option<&str>) -> Result<Runnable, String> {
    let mut runnable: Vec<(&str, bool)> = definitions_in(sema, files)
        .filter_map(|def| match def.kind {
            DefKind::ComponentInstanceDiagram => Some((def.fqn.as_str(), true)),
            _ if is_runnable(sema, def) => Some((def.fqn.as_str(), false)),
            _ => None,
        })
        .collect();
    runnable.sort();
    runnable.dedup();
    let Some(name) = name else {
        return match runnable[..] {
            [(fqn, true)] => Ok(Runnable::Pipeline(fqn.to_string())),
            [(fqn, false)] => Ok(Runnable::Activity(fqn.to_string())),
            [] => Err("the files have no diagram that can run (a component-instance diagram, or an activity diagram without parameters)".into()),
            _ => Err(format!(
                "name the diagram to run with --diagram: {}",
                listed(runnable.iter().map(|(fqn, _)| *fqn))
            )),
        };
    };
    let pipelines: Vec<&str> =
        runnable.iter().filter(|(fqn, is)| *is && names_diagram(name, fqn)).map(|(f, _)| *f).collect();
    match pipelines[..] {
        [fqn] => Ok(Runnable::Pipeline(fqn.to_string())),
        [] => Ok(Runnable::Activity(name.to_string())),
        _ => Err(several("component-instance diagrams", name, &pipelines)),
    }
}

/// The fully qualified name of the component-instance diagram of `files` named `name`; `Err`
/// says why none is meant, listing the pipelines there are.
pub fn pipeline_named(sema: &Semantics<'_>, files: &[FileId], name: &str) -> Result<String, String> {
    let mut pipelines: Vec<&str> = definitions_in(sema, files)
        .filter(|def| matches!(def.kind, DefKind::ComponentInstanceDiagram))
        .map(|def| def.fqn.as_str())
        .collect();
    pipelines.sort();
    pipelines.dedup();
    let named: Vec<&str> = pipelines.iter().copied().filter(|fqn| names_diagram(name, fqn)).collect();
    match named[..] {
        [fqn] => Ok(fqn.to_string()),
        [] => Err(format!("no component-instance diagram named `{name}`; pipelines: {}", listed(pipelines))),
        _ => Err(several("component-instance diagrams", name, &named)),
    }
}

/// The activity diagram of `files` named `name`; `Err` says why none is meant (none or several
/// have the name, listing those that can run).
pub fn activity_named<'db>(sema: &Semantics<'db>, files: &[FileId], name: &str) -> Result<&'db Definition, String> {
    let candidates: Vec<&Definition> =
        definitions_in(sema, files).filter(|def| matches!(def.kind, DefKind::Activity(_))).collect();
    let named: Vec<&Definition> = candidates.iter().copied().filter(|def| names_diagram(name, &def.fqn)).collect();
    match named[..] {
        [def] => Ok(def),
        [] => {
            let mut runnable: Vec<&str> =
                candidates.iter().filter(|def| is_runnable(sema, def)).map(|def| def.fqn.as_str()).collect();
            runnable.sort();
            Err(format!("no activity diagram named `{name}`; diagrams that can run: {}", listed(runnable)))
        }
        _ => Err(several("activity diagrams", name, &named.iter().map(|d| d.fqn.as_str()).collect::<Vec<_>>())),
    }
}

/// The definitions declared in `files`.
fn definitions_in<'a, 'db>(sema: &Semantics<'db>, files: &'a [FileId]) -> impl Iterator<Item = &'db Definition> + 'a
where
    'db: 'a,
{
    sema.def_map().definitions.values().flatten().filter(move |def| files.contains(&def.file))
}

/// Names for a message: `a, b` or `none`.
fn listed<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let names: Vec<&str> = names.into_iter().collect();
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// Why `name` means none of several diagrams of a kind.
fn several(kind: &str, name: &str, fqns: &[&str]) -> String {
    format!("several {kind} are named `{name}`: {}; name one fully qualified", fqns.join(", "))
}
