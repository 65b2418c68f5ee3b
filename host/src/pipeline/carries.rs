//! What a run would find missing, found before it, in the editor too: whether the items that
//! reach a component carry what it needs — a black image of the frame's own, the scene's true
//! distances, a camera's grid — followed from each source down the bindings (E0405 at the
//! component).

use gudsl_model::hir::pipeline::PipelinePlan;

use super::{
    components::{self, Carries, Component, Need},
    ErrorKind, PipelineError,
};
use crate::access::ModelFiles;

/// Every component given items that lack what it needs, with the providers whose items lack it.
pub fn that_lack(plan: &PipelinePlan, made: &[Option<Box<dyn Component>>], files: &ModelFiles) -> Vec<PipelineError> {
    let gives = carried(plan, made);
    let mut errors = Vec::new();
    for (index, (stage, component)) in plan.stages.iter().zip(made).enumerate() {
        let Some(need) = component.as_ref().and_then(|c| c.needs()) else { continue };
        let (what, missing, advice) = match need {
            Need::Black(advice) => ("raw frames", "have no black image of their own", advice),
            Need::Truth(advice) => ("depth images", "have no ground truth", advice),
            Need::Organized(advice) => ("point clouds", "are accumulated, not on a camera's grid", advice),
        };
        let lacks = |c: Carries| match need {
            Need::Black(_) => !c.black,
            Need::Truth(_) => !c.truth,
            Need::Organized(_) => !c.organized,
        };
        let mut lacking: Vec<&str> = plan
            .bindings
            .iter()
            .filter(|b| b.processor.stage == index && lacks(gives[b.provider.stage]))
            .map(|b| plan.stages[b.provider.stage].instance.as_str())
            .collect();
        lacking.dedup();
        if lacking.is_empty() {
            continue;
        }
        let from = lacking.iter().map(|p| format!("`{p}`")).collect::<Vec<_>>().join(", ");
        let params = components::Params { stage, providers: 0, files };
        errors.push(params.error("", ErrorKind::Mismatch, format!("the {what} from {from} {missing}: {advice}")));
    }
    errors
}

/// What each stage's items carry: from what every source's carry, down the bindings, until
/// nothing changes (a stage's items carry what all that reach it carry, passed on or not by
/// it; what carries are only lost on the way, so this ends).
fn carried(plan: &PipelinePlan, made: &[Option<Box<dyn Component>>]) -> Vec<Carries> {
    let mut gives = vec![Carries::ALL; plan.stages.len()];
    let mut changed = true;
    while changed {
        changed = false;
        for index in 0..plan.stages.len() {
            let arriving = plan
                .bindings
                .iter()
                .filter(|b| b.processor.stage == index)
                .fold(Carries::ALL, |all, b| all.and(gives[b.provider.stage]));
            let given = made[index].as_ref().map_or(arriving, |c| c.carries(arriving));
            if given != gives[index] {
                gives[index] = given;
                changed = true;
            }
        }
    }
    gives
}
