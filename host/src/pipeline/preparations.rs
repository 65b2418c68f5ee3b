//! Pipelines prepared once: what `gudsl check` and the editor's diagnostics prepared (plan
//! checked, kernels generated, components made, files' headers read) is kept, keyed by diagram,
//! while neither the plan, the kernels it runs nor a file it names changed (a file by its
//! length and modification time); a run takes the prepared pipeline from here instead of
//! preparing it again, and a check of an unchanged model reads no file. Where the model changed
//! only where the diagram sits (an edit above it), the kept problems move with it: typing
//! reads no file until the pipeline itself changes.

use std::{
    collections::HashMap,
    path::{Path, PathBuf},
    sync::{
        atomic::{AtomicUsize, Ordering},
        Mutex, RwLock,
    },
};

use gudsl_files::Stamp;

use gudsl_model::{
    hir::{pipeline::PipelinePlan, DefKind, Diagnostic, Severity},
    syntax::TextRange,
    Analysis, Cancellable, FileId,
};

use crate::access::{Access, ModelFiles};

use super::{behaviors, prepare, replay, Behaviors, ErrorKind, PipelineError, PreparedPipeline};

/// The pipelines prepared for a model, by diagram (fully qualified).
#[derive(Default)]
pub struct Preparations {
    /// What the pipelines may read.
    access: RwLock<Access>,
    entries: Mutex<HashMap<String, Entry>>,
    /// How many pipelines were prepared (tests count that typing prepares none again).
    made: AtomicUsize,
}

/// One diagram's preparation and what it was prepared from.
struct Entry {
    key: Key,
    /// The plan as it was, with the ranges its problems and its pipeline point at.
    placed: PipelinePlan,
    /// The prepared pipeline (a run takes it, and the entry with it), or every problem found.
    prepared: Result<PreparedPipeline, Vec<PipelineError>>,
}

/// What a preparation depends on besides the model's folder: the plan without its ranges.
#[derive(PartialEq)]
struct Key {
    plan: PipelinePlan,
    behaviors: Behaviors,
    /// Each file it reads with its length and modification time (`None`: missing, unreadable).
    files: Vec<(PathBuf, Option<Stamp>)>,
}

impl Key {
    /// The key of `plan` now: its kernels and the state of every file it reads.
    fn of(plan: &PipelinePlan, behaviors: Behaviors, model_files: &ModelFiles) -> Key {
        let files = plan.stages.iter().flat_map(|stage| replay::read_files(stage, model_files)).collect();
        Key { plan: placeless(plan), behaviors, files }
    }
}

impl Preparations {
    /// Preparations that read what `access` allows.
    pub fn new(access: Access) -> Preparations {
        Preparations { access: RwLock::new(access), ..Preparations::default() }
    }

    /// From now on read what `access` allows (the editor learns its workspace folders and trust
    /// after starting); what was prepared under other access is forgotten.
    pub fn set_access(&self, access: Access) {
        let mut current = self.access.write().unwrap_or_else(|e| e.into_inner());
        if *current != access {
            *current = access;
            self.entries.lock().unwrap_or_else(|e| e.into_inner()).clear();
        }
    }

    /// What access it reads with.
    pub fn access(&self) -> Access {
        self.access.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// What keeps the pipeline `plan` (one the plan found no problem in) from running, as
    /// diagnostics of its file: E0404 and E0405 at the instance or parameter concerned, else at
    /// the diagram's name. A component the runtime cannot run is not one: the model is right,
    /// only a run refuses it. Nothing while the workspace is not trusted (no file is read).
    /// Prepared again only when the plan, its kernels or a file changed.
    pub fn check(&self, plan: &PipelinePlan, behaviors: Behaviors, model_dir: &Path) -> Vec<Diagnostic> {
        let access = self.access();
        if !access.trusted() {
            return Vec::new();
        }
        let files = access.files(model_dir);
        let key = Key::of(plan, behaviors, &files);
        let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(entry) = entries.get_mut(&plan.diagram).filter(|entry| entry.key == key) {
            entry.move_to(plan);
            return problems(entry, plan);
        }
        // Prepared without the lock: a slow file delays this check only, not the others.
        drop(entries);
        self.made.fetch_add(1, Ordering::Relaxed);
        let prepared = prepare(plan, &key.behaviors, &files);
        let entry = Entry { key, placed: plan.clone(), prepared };
        let diagnostics = problems(&entry, plan);
        self.entries.lock().unwrap_or_else(|e| e.into_inner()).insert(plan.diagram.clone(), entry);
        diagnostics
    }

    /// The pipeline `plan` ready to run: the one a check prepared when nothing it depends on
    /// changed since, else prepared now; or every problem found.
    pub fn take(
        &self,
        plan: &PipelinePlan,
        behaviors: Behaviors,
        model_dir: &Path,
    ) -> Result<PreparedPipeline, Vec<PipelineError>> {
        let files = self.access().files(model_dir);
        let key = Key::of(plan, behaviors, &files);
        let taken = self.entries.lock().unwrap_or_else(|e| e.into_inner()).remove(&plan.diagram);
        match taken {
            Some(mut entry) if entry.key == key => {
                entry.move_to(plan);
                entry.prepared
            }
            _ => prepare(plan, &key.behaviors, &files),
        }
    }

    /// How many pipelines it has prepared for checks.
    pub fn made(&self) -> usize {
        self.made.load(Ordering::Relaxed)
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

    /// A pipeline of its own for `plan` of `analysis`'s model, prepared now: the one the check
    /// prepared stays for the check and for a run (a live preview prepares at every edit).
    pub fn prepare_apart(
        &self,
        analysis: &Analysis,
        plan: &PipelinePlan,
    ) -> Cancellable<Result<PreparedPipeline, Vec<PipelineError>>> {
        let behaviors = analysis.with_semantics(|sema| behaviors(sema, plan))?;
        Ok(prepare(plan, &behaviors, &self.access().files(&model_dir(analysis, plan.file))))
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

/// What keeps a prepared pipeline from running, as diagnostics placed in `plan`: not that the
/// runtime cannot run a component (the model is right, only a run refuses it).
fn problems(entry: &Entry, plan: &PipelinePlan) -> Vec<Diagnostic> {
    let errors = match &entry.prepared {
        Ok(prepared) => &prepared.warnings,
        Err(errors) => errors,
    };
    errors
        .iter()
        .filter(|error| error.kind != ErrorKind::NotRunnable)
        .map(|error| Diagnostic {
            code: error.code(),
            severity: if error.kind == ErrorKind::Ineffective { Severity::Warning } else { Severity::Error },
            range: error.range.unwrap_or(plan.name_range),
            message: error.message.clone(),
            suggestion: None,
            related: Vec::new(),
        })
        .collect()
}

impl Entry {
    /// The preparation placed where `plan` (the same plan but for its ranges) sits.
    fn move_to(&mut self, plan: &PipelinePlan) {
        if self.placed == *plan {
            return;
        }
        match &mut self.prepared {
            Ok(prepared) => prepared.move_to(plan),
            Err(errors) => {
                for error in errors {
                    error.range = error.range.map(|range| moved(range, &self.placed, plan));
                }
            }
        }
        self.placed = plan.clone();
    }
}

/// `plan` with every range cleared: what a preparation depends on (ranges only place its
/// problems).
fn placeless(plan: &PipelinePlan) -> PipelinePlan {
    let mut plan = plan.clone();
    plan.name_range = TextRange::default();
    for stage in &mut plan.stages {
        stage.range = TextRange::default();
        for param in &mut stage.params {
            param.written = param.written.map(|_| TextRange::default());
        }
    }
    for binding in &mut plan.bindings {
        binding.range = TextRange::default();
    }
    plan
}

/// Where `range` of the plan `from` is in `to`, the same plan placed elsewhere: the diagram's
/// name, an instance's name, a parameter's value or a binding moved with it.
fn moved(range: TextRange, from: &PipelinePlan, to: &PipelinePlan) -> TextRange {
    let names = std::iter::once((from.name_range, to.name_range));
    let stages = from.stages.iter().zip(&to.stages).flat_map(|(a, b)| {
        let params = a.params.iter().zip(&b.params).filter_map(|(p, q)| Some((p.written?, q.written?)));
        std::iter::once((a.range, b.range)).chain(params)
    });
    let bindings = from.bindings.iter().zip(&to.bindings).map(|(a, b)| (a.range, b.range));
    names.chain(stages).chain(bindings).find(|(was, _)| *was == range).map_or(range, |(_, is)| is)
}

/// The folder a model file's relative paths resolve against.
pub fn model_dir(analysis: &Analysis, file: FileId) -> PathBuf {
    let parent = Path::new(analysis.file_path(file)).parent().filter(|p| !p.as_os_str().is_empty());
    parent.unwrap_or(Path::new(".")).to_path_buf()
}

#[cfg(test)]
mod tests {
    use gudsl_model::{syntax::TextSize, AnalysisHost};

    use super::*;

    /// A pipeline whose black image does not exist (E0404 at `channelA`'s value), in `dir`.
    fn model(above: &str) -> String {
        format!(
            "{above}ComponentInstanceDiagram P\n{{\n    import ToF.*;\n    Camera instantiates SimulatedCamera (frames = 1)\n    {{\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Black.In.frame ]\n    }}\n    Black instantiates BlackImageCorrection (channelA = \"missing.npy\", channelB = \"missing.npy\")\n    {{\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n    }}\n}}\n"
        )
    }

    #[test]
    fn typing_above_a_pipeline_moves_its_problems_without_preparing_it_again() {
        let dir = std::env::temp_dir().join(format!("gudsl-preparations-{}", std::process::id()));
        let path = dir.join("p.gudsl").display().to_string();
        let (mut host, files) = AnalysisHost::with_files([(path, model(""))]);
        let preparations = Preparations::default();
        let before = preparations.file_diagnostics(&host.analysis(), files[0]).unwrap();
        assert!(!before.is_empty() && before.iter().all(|d| d.code.as_str() == "E0404"), "{before:?}");
        let comment = "// a line typed above\n";
        host.set_file_text(files[0], model(comment));
        let after = preparations.file_diagnostics(&host.analysis(), files[0]).unwrap();
        let shifted: Vec<TextRange> = before.iter().map(|d| d.range + TextSize::of(comment)).collect();
        assert_eq!(after.iter().map(|d| d.range).collect::<Vec<_>>(), shifted);
        assert_eq!(preparations.made(), 1, "prepared once");
        // A change of the pipeline itself prepares it again.
        host.set_file_text(files[0], model(comment).replace("frames = 1", "frames = 2"));
        preparations.file_diagnostics(&host.analysis(), files[0]).unwrap();
        assert_eq!(preparations.made(), 2);
    }
}
