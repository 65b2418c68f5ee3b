//! Pipelines prepared once: what `gudsl check` and the editor's diagnostics prepared (plan
//! checked, kernels generated, components made, files' headers read) is kept, keyed by diagram,
//! while neither the plan, the kernels it runs nor a file it names changed (a file by its
//! length and modification time); a run takes the prepared pipeline from here instead of
//! preparing it again, and a check of an unchanged model reads no file.

use std::{
    collections::HashMap,
    path::{Path, PathBuf},
    sync::Mutex,
    time::SystemTime,
};

use gudsl_model::{
    hir::{
        pipeline::{PipelinePlan, Value},
        DefKind, Diagnostic, Severity,
    },
    Analysis, Cancellable, FileId,
};

use super::{behaviors, prepare, Behaviors, ErrorKind, PipelineError, PreparedPipeline};

/// The pipelines prepared for a model, by diagram (fully qualified).
#[derive(Default)]
pub struct Preparations {
    entries: Mutex<HashMap<String, Entry>>,
}

/// One diagram's preparation and what it was prepared from.
struct Entry {
    key: Key,
    /// The prepared pipeline until a run takes it, or every problem found.
    prepared: Result<Option<PreparedPipeline>, Vec<PipelineError>>,
}

/// What a preparation depends on besides the model's folder.
#[derive(PartialEq)]
struct Key {
    plan: PipelinePlan,
    behaviors: Behaviors,
    files: Vec<(PathBuf, Option<Stamp>)>,
}

/// A file as it was: its length and modification time (`None`: missing or unreadable).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Key {
    /// The key of `plan` now: its kernels and the state of every file it reads.
    fn of(plan: &PipelinePlan, behaviors: Behaviors, model_dir: &Path) -> Key {
        let texts = plan.stages.iter().flat_map(|stage| &stage.params).filter_map(|param| match &param.value {
            Value::Text(text) if param.input_file && !text.is_empty() => Some(model_dir.join(text)),
            _ => None,
        });
        let files = texts
            .map(|path| {
                let stamp = std::fs::metadata(&path).ok().map(|m| Stamp { len: m.len(), modified: m.modified().ok() });
                (path, stamp)
            })
            .collect();
        Key { plan: plan.clone(), behaviors, files }
    }
}

impl Preparations {
    /// What keeps the pipeline `plan` (one the plan found no problem in) from running, as
    /// diagnostics of its file: E0404 and E0405 at the instance or parameter concerned, else at
    /// the diagram's name. A component the runtime cannot run is not one: the model is right,
    /// only a run refuses it. Prepared again only when the plan, its kernels or a file changed.
    pub fn check(&self, plan: &PipelinePlan, behaviors: Behaviors, model_dir: &Path) -> Vec<Diagnostic> {
        let key = Key::of(plan, behaviors, model_dir);
        let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        let entry = match entries.get(&plan.diagram) {
            Some(entry) if entry.key == key => entry,
            _ => {
                let prepared = prepare(plan, &key.behaviors, model_dir).map(Some);
                entries.entry(plan.diagram.clone()).insert_entry(Entry { key, prepared }).into_mut()
            }
        };
        let Err(errors) = &entry.prepared else { return Vec::new() };
        errors
            .iter()
            .filter(|error| error.kind != ErrorKind::NotRunnable)
            .map(|error| Diagnostic {
                code: error.code(),
                severity: Severity::Error,
                range: error.range.unwrap_or(plan.name_range),
                message: error.message.clone(),
                suggestion: None,
                related: Vec::new(),
            })
            .collect()
    }

    /// The pipeline `plan` ready to run: the one a check prepared when nothing it depends on
    /// changed since, else prepared now; or every problem found.
    pub fn take(
        &self,
        plan: &PipelinePlan,
        behaviors: Behaviors,
        model_dir: &Path,
    ) -> Result<PreparedPipeline, Vec<PipelineError>> {
        let key = Key::of(plan, behaviors, model_dir);
        let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        match entries.remove(&plan.diagram) {
            Some(Entry { key: kept, prepared: Ok(Some(prepared)) }) if kept == key => Ok(prepared),
            Some(Entry { key: kept, prepared: Err(errors) }) if kept == key => Err(errors),
            _ => prepare(plan, &key.behaviors, model_dir),
        }
    }

    /// What keeps the pipelines declared in `file` from running (E0404, E0405), for those whose
    /// plan has no problems of its own.
    pub fn file_diagnostics(&self, analysis: &Analysis, file: FileId) -> Cancellable<Vec<Diagnostic>> {
        let diagrams: Vec<String> = analysis.with_semantics(|sema| {
            sema.file_diagrams(file)
                .filter(|def| matches!(def.kind, DefKind::ComponentInstanceDiagram))
                .map(|def| def.fqn.clone())
                .collect()
        })?;
        let mut out = Vec::new();
        for fqn in diagrams {
            match analysis.pipeline_plan(&fqn)? {
                Some(plan) if plan.file == file && plan.diagnostics.is_empty() => {
                    let behaviors = analysis.with_semantics(|sema| behaviors(sema, &plan))?;
                    out.extend(self.check(&plan, behaviors, &model_dir(analysis, file)));
                }
                _ => {}
            }
        }
        Ok(out)
    }

    /// The pipeline `plan` of `analysis`'s model ready to run (see [`Preparations::take`]).
    pub fn take_for(
        &self,
        analysis: &Analysis,
        plan: &PipelinePlan,
    ) -> Cancellable<Result<PreparedPipeline, Vec<PipelineError>>> {
        let behaviors = analysis.with_semantics(|sema| behaviors(sema, plan))?;
        Ok(self.take(plan, behaviors, &model_dir(analysis, plan.file)))
    }
}

/// The folder a model file's relative paths resolve against.
pub fn model_dir(analysis: &Analysis, file: FileId) -> PathBuf {
    Path::new(analysis.file_path(file)).parent().unwrap_or(Path::new(".")).to_path_buf()
}
