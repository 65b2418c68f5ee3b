//! Images of sizes that cannot meet (E0405), found before a run, in the editor too: each
//! source's image size followed down the bindings, each component asked whether the sizes it is
//! given can meet in it.

use std::collections::BTreeSet;

use gudsl_model::hir::pipeline::PipelinePlan;

use super::{
    components::{self, Component, Size, SizesByPort},
    ErrorKind, PipelineError,
};
use crate::access::ModelFiles;

/// Images of sizes that cannot meet (E0405), found by following each source's image size down
/// the bindings until nothing changes (a filter gives images of the sizes it is given; a stage
/// that could not be made passes them on).
pub fn that_cannot_meet(
    plan: &PipelinePlan,
    made: &[Option<Box<dyn Component>>],
    files: &ModelFiles,
) -> Vec<PipelineError> {
    let arriving = |gives: &[BTreeSet<Size>], index: usize| {
        let mut sizes = SizesByPort::new();
        for binding in plan.bindings.iter().filter(|b| b.processor.stage == index) {
            sizes.entry(binding.processor.port.clone()).or_default().extend(&gives[binding.provider.stage]);
        }
        sizes
    };
    let mut gives: Vec<BTreeSet<Size>> = vec![BTreeSet::new(); plan.stages.len()];
    // The sets only grow, and a stage gives at most the sizes that exist: this ends.
    let mut changed = true;
    while changed {
        changed = false;
        for index in 0..plan.stages.len() {
            let given = match made[index].as_ref().and_then(|c| c.image_size()) {
                Some(size) => BTreeSet::from([size]),
                None => arriving(&gives, index).into_values().flatten().collect(),
            };
            if given != gives[index] {
                gives[index] = given;
                changed = true;
            }
        }
    }
    let mut errors = Vec::new();
    for (index, (stage, component)) in plan.stages.iter().zip(made).enumerate() {
        let Some(component) = component else { continue };
        if let Err((param, message)) = component.sizes_meet(&arriving(&gives, index)) {
            let params = components::Params { stage, providers: 0, files };
            errors.push(params.error(param.unwrap_or(""), ErrorKind::Mismatch, message));
        }
    }
    errors
}
