//! The findIndex reduction of Listings 34–39 written by hand in WGSL (`find_index.wgsl`): the
//! yardstick for the kernels the generator makes of `samples/seed/listing34_39_find_index.gudsl`.
//! Both stages in one module, each entry point a [`Program`](crate::program::Program) with
//! [`BINDINGS`], work-groups of `group_size` (a pipeline constant, a power of two).

use crate::program::{BindingKind, BindingSpec};

/// Both stages.
pub const WGSL: &str = include_str!("find_index.wgsl");
/// Stage 1: each work-group's candidate.
pub const FIRST_STAGE: &str = "first_stage";
/// Stage 2: one work-group reduces the groups' candidates.
pub const SECOND_STAGE: &str = "second_stage";
/// The pipeline constant of the work-group size.
pub const GROUP_SIZE: &str = "group_size";

/// The parameters at 0, the elements at 1, the groups' candidates at 2, the result at 3.
pub const BINDINGS: [BindingSpec; 4] = [
    BindingSpec { binding: 0, kind: BindingKind::Uniform },
    BindingSpec { binding: 1, kind: BindingKind::Storage { writable: false } },
    BindingSpec { binding: 2, kind: BindingKind::Storage { writable: true } },
    BindingSpec { binding: 3, kind: BindingKind::Storage { writable: true } },
];

/// The parameter block: `count` elements searched for the first >= `value`, `per_item` of them
/// per work-item, `groups` work-groups in stage 1.
pub fn params(count: u32, value: u32, per_item: u32, groups: u32) -> Vec<u8> {
    [count, value, per_item, groups].iter().flat_map(|v| v.to_le_bytes()).collect()
}
