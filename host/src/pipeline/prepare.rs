//! Preparing a pipeline: a component for each stage of the plan, made from its parameters and
//! the files it reads, and every problem that would stop a run found before it starts (sizes
//! that cannot meet, items that lack what a component needs, a source too short).

use gudsl_model::{ast::ClassKind, hir::pipeline::PipelinePlan};

use super::{apart::Mode, carries, components, replay, sizes, Behaviors, ErrorKind, PipelineError, PreparedPipeline};
use crate::access::ModelFiles;

/// Makes the plan's components: each a component of the ToF library or of the workspace (with
/// the kernels of `behaviors`), with its parameters and the files it reads (as `files`
/// allows) checked; every problem found, not just the first.
pub fn prepare(
    plan: &PipelinePlan,
    behaviors: &Behaviors,
    files: &ModelFiles,
) -> Result<PreparedPipeline, Vec<PipelineError>> {
    let mut errors = Vec::new();
    let mut made = Vec::new();
    for (index, stage) in plan.stages.iter().enumerate() {
        let providers = plan.bindings.iter().filter(|b| b.processor.stage == index).count();
        match components::make(stage, providers, files, behaviors) {
            Ok(component) => made.push(Some(component)),
            Err(mut problems) => {
                errors.append(&mut problems);
                made.push(None);
            }
        }
    }
    if plan.stages.is_empty() {
        errors.push(PipelineError {
            kind: ErrorKind::NotRunnable,
            stage: None,
            range: Some(plan.name_range),
            message: format!("`{}` has no instances to run", plan.diagram),
        });
    } else if plan.bindings.is_empty() {
        errors.push(PipelineError {
            kind: ErrorKind::NotRunnable,
            stage: None,
            range: Some(plan.name_range),
            message: format!("`{}` binds nothing: bind the sources' ports to filters and sinks", plan.diagram),
        });
    }
    // Checked even where another stage cannot run (it passes its sizes on), so the editor
    // shows a mismatch beside a component only `run` refuses.
    errors.extend(sizes::that_cannot_meet(plan, &made, files));
    errors.extend(carries::that_lack(plan, &made, files));
    let frames = made.iter().flatten().filter_map(|c| c.frames()).max().unwrap_or(0);
    if errors.is_empty() && frames == 0 {
        errors.push(PipelineError {
            kind: ErrorKind::NotRunnable,
            stage: None,
            range: Some(plan.name_range),
            message: format!("`{}` has no source: nothing produces frames", plan.diagram),
        });
    }
    errors.extend(plan.stages.iter().zip(&made).filter_map(|(stage, component)| {
        let (param, why) = component.as_ref()?.too_short(frames)?;
        Some(components::Params { stage, providers: 0, files }.error(param, ErrorKind::Input, why))
    }));
    let warnings: Vec<PipelineError> = plan
        .stages
        .iter()
        .zip(&made)
        .filter_map(|(stage, component)| {
            let (param, why) = component.as_ref()?.cannot_act(frames)?;
            let params = components::Params { stage, providers: 0, files };
            Some(params.error(param, ErrorKind::Ineffective, why))
        })
        .collect();
    if errors.is_empty() {
        let modes = (0..plan.stages.len())
            .map(|i| match plan.stages[i].kind {
                _ if !plan.bindings.iter().any(|b| b.processor.stage == i && b.is_async) => Mode::InOrder,
                ClassKind::Sink => Mode::WritesApart,
                ClassKind::Filter => Mode::ProcessesApart,
                _ => Mode::InOrder,
            })
            .collect();
        let mut prepared = PreparedPipeline {
            plan: plan.clone(),
            writers: made.iter().map(|_| None).collect(),
            components: made,
            modes,
            frames,
            warnings,
            keys: replay::keys(plan, behaviors, files),
            replay: None,
            flows: Vec::new(),
            submissions: Vec::new(),
            frame_spans: Vec::new(),
            overlap: true,
            fused_into: Vec::new(),
        };
        prepared.fuse(true);
        Ok(prepared)
    } else {
        errors.extend(warnings);
        Err(errors)
    }
}
