//! What one run of a pipeline gave, kept to be replayed in the next (the live preview): a
//! stage that neither changed since the kept run (its class, parameters, bindings into it, the
//! files it reads, the kernels it calls: its [`StageKey`]) nor is downstream of a stage that
//! did gives the items it gave then instead of running again — a source is not re-read or
//! re-simulated for a later stage's parameter. Sinks always run: what they write is the
//! preview.

use std::{collections::HashMap, path::PathBuf};

use gudsl_files::Stamp;
use gudsl_model::{
    ast::ClassKind,
    hir::pipeline::{PipelinePlan, Stage, Value},
    syntax::TextRange,
};

use super::{
    components::{Behaviors, Outputs},
    data,
    executor::Executor,
    files::stamped_path,
    report::Figure,
};
use crate::access::ModelFiles;

/// What a stage's items depend on besides its providers' items.
#[derive(Debug, Clone, PartialEq)]
pub struct StageKey {
    /// The stage without the ranges that place it.
    stage: Stage,
    /// The bindings into it: the provider's instance and port, its own port, the mode.
    inputs: Vec<(String, String, String, bool, bool, usize)>,
    /// Each file it reads with its length and modification time.
    files: Vec<(PathBuf, Option<Stamp>)>,
    /// The kernels its `process` calls (a workspace component's).
    kernels: Vec<Option<Result<gudsl_codegen::Kernel, String>>>,
    /// The stages its kernel runs inside (`fusion.rs`): what it gives them differs.
    inside: Vec<usize>,
}

impl StageKey {
    /// The stage's kernel runs inside these stages (`fusion.rs`).
    pub fn runs_inside(&mut self, stages: &[usize]) {
        self.inside = stages.to_vec();
    }
}

/// The key of every stage of `plan`.
pub fn keys(plan: &PipelinePlan, behaviors: &Behaviors, files: &ModelFiles) -> Vec<StageKey> {
    (0..plan.stages.len()).map(|index| key(plan, index, behaviors, files)).collect()
}

fn key(plan: &PipelinePlan, index: usize, behaviors: &Behaviors, files: &ModelFiles) -> StageKey {
    let mut stage = plan.stages[index].clone();
    stage.range = TextRange::default();
    for param in &mut stage.params {
        param.written = None;
    }
    let mut inputs: Vec<_> = plan
        .bindings
        .iter()
        .filter(|b| b.processor.stage == index)
        .map(|b| {
            let provider = plan.stages[b.provider.stage].instance.clone();
            (provider, b.provider.port.clone(), b.processor.port.clone(), b.is_async, b.is_buffered, b.buffer_size)
        })
        .collect();
    inputs.sort();
    StageKey {
        files: read_files(&stage, files),
        kernels: stage.behavior.iter().map(|call| behaviors.get(&call.diagram).cloned()).collect(),
        stage,
        inputs,
        inside: Vec::new(),
    }
}

/// The files `stage` reads, each with its stamp now.
pub fn read_files(stage: &Stage, files: &ModelFiles) -> Vec<(PathBuf, Option<Stamp>)> {
    let texts = stage.params.iter().filter_map(|param| match &param.value {
        Value::Text(text) if param.input_file && !text.is_empty() => Some(files.path(text)),
        _ => None,
    });
    texts.map(|path| (path.clone(), files.stamp(&stamped_path(&path)))).collect()
}

/// What a stage gave in one frame: during the frame, and after the frame's reads.
#[derive(Clone, Default)]
pub struct Gave {
    pub given: Outputs,
    pub later: Outputs,
}

/// What the last whole run gave, by instance, for its first `frames` frames.
#[derive(Default)]
pub struct Kept {
    frames: usize,
    keys: HashMap<String, StageKey>,
    gave: HashMap<String, Vec<Gave>>,
    figures: HashMap<String, Vec<Figure>>,
}

/// One run's replay: the stages that replay what `Kept` holds, and what the others give,
/// recorded frame by frame.
pub struct Replay {
    replays: Vec<Option<Vec<Gave>>>,
    recorded: Vec<Vec<Gave>>,
}

impl Replay {
    /// The replay of `plan` (stages keyed `keys`) over `frames` frames after `kept`: a stage
    /// replays when it is no sink, its key and every upstream stage's are as kept, and the kept
    /// run had as many frames.
    pub fn after(kept: &Kept, plan: &PipelinePlan, keys: &[StageKey], frames: usize) -> Replay {
        let same = |i: usize| kept.frames == frames && kept.keys.get(&plan.stages[i].instance) == Some(&keys[i]);
        let mut dirty: Vec<bool> = (0..plan.stages.len()).map(|i| !same(i)).collect();
        // Downstream of a changed stage, through every binding (a buffered loop too).
        while let Some(b) = plan.bindings.iter().find(|b| dirty[b.provider.stage] && !dirty[b.processor.stage]) {
            dirty[b.processor.stage] = true;
        }
        let replays = plan
            .stages
            .iter()
            .zip(&dirty)
            .map(|(stage, &dirty)| match dirty || stage.kind == ClassKind::Sink {
                true => None,
                false => kept.gave.get(&stage.instance).filter(|gave| gave.len() == frames).cloned(),
            })
            .collect();
        Replay { replays, recorded: vec![Vec::new(); plan.stages.len()] }
    }

    /// Whether stage `index` replays.
    pub fn replays(&self, index: usize) -> bool {
        self.replays[index].is_some()
    }

    /// What stage `index` gave in `frame` when it replays.
    pub fn gave(&self, index: usize, frame: usize) -> Option<&Gave> {
        self.replays[index].as_ref()?.get(frame)
    }

    /// Records what stage `index` gave in `frame` (`later`: after the frame's reads), its images
    /// copied so that they outlive the run.
    pub fn record(&mut self, device: &mut Executor, (index, frame): (usize, usize), produced: &Outputs, later: bool) {
        if self.replays(index) {
            return;
        }
        let frames = &mut self.recorded[index];
        if frames.len() <= frame {
            frames.resize_with(frame + 1, Gave::default);
        }
        let kept = produced.iter().map(|(port, d)| (port.clone(), data::detached(device, d)));
        let gave = &mut frames[frame];
        if later { &mut gave.later } else { &mut gave.given }.extend(kept);
    }

    /// What to keep for the next run after this whole run of `frames` frames (`figures`: what
    /// the stages that ran measured; a replayed stage keeps what it measured before).
    pub fn keep(
        self,
        kept: Kept,
        (plan, keys): (&PipelinePlan, &[StageKey]),
        frames: usize,
        figures: &[Figure],
    ) -> Kept {
        let mut next = Kept { frames, ..Kept::default() };
        let mut old = kept;
        for (index, (stage, recorded)) in plan.stages.iter().zip(self.recorded).enumerate() {
            let instance = &stage.instance;
            next.keys.insert(instance.clone(), keys[index].clone());
            let (gave, measured) = match self.replays[index].is_some() {
                true => (old.gave.remove(instance), old.figures.remove(instance).unwrap_or_default()),
                false => {
                    let mut recorded = recorded;
                    recorded.resize_with(frames, Gave::default);
                    (Some(recorded), figures.iter().filter(|f| &f.stage == instance).cloned().collect())
                }
            };
            next.gave.extend(gave.map(|gave| (instance.clone(), gave)));
            next.figures.insert(instance.clone(), measured);
        }
        next
    }

    /// What the replayed stages measured when they ran.
    pub fn figures<'k>(&'k self, kept: &'k Kept, plan: &'k PipelinePlan) -> impl Iterator<Item = Figure> + 'k {
        let replayed = plan.stages.iter().zip(&self.replays).filter(|(_, r)| r.is_some());
        replayed.flat_map(|(stage, _)| kept.figures.get(&stage.instance).into_iter().flatten().cloned())
    }
}
