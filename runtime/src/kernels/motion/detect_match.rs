//! Motion detection and block matching fused into one pass (`detect_match.wgsl`): raw frame →
//! flow, mask. Each pixel's mask is its own M > θ and only its own mask decides whether it is
//! matched, so the pass gives exactly what [`super::DetectMotion`] then [`super::MatchBlocks`]
//! give, one dispatch and one read of the frame fewer. [`DetectMatchAround`] restricts the
//! search around the direction a buffer holds (`detect_match_around.wgsl`: the frame before's,
//! as [`super::MeanDirection`] wrote it on the GPU).

use super::{detect, match_blocks, MatchBlocks};
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// Detection with threshold θ, then matching as [`MatchBlocks`] does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DetectMatch {
    pub(crate) theta: f32,
    pub(crate) matching: MatchBlocks,
}

impl Unit for DetectMatch {
    const NAME: &'static str = "detect_match";
    const SOURCE: &'static str = concat!(
        include_str!("match_search.wgsl"),
        include_str!("motion_measure.wgsl"),
        include_str!("detect_match_pixel.wgsl"),
        include_str!("detect_match.wgsl")
    );
    const INPUTS: &'static [Option<usize>] = &[Some(8)];
    type Params = super::match_blocks::Params;

    fn params(&self, inputs: &[Shape]) -> Self::Params {
        self.matching.params(inputs).with_theta(self.theta)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 2, ..inputs[0] }, Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        let [_, mask] = detect(inputs[0], self.theta);
        let MatchBlocks { window, restriction, subpixel } = self.matching;
        vec![match_blocks(inputs[0], &mask, window, restriction, subpixel), mask]
    }
}

/// Detection with threshold θ and matching over MWS `window`, restricted to `half_width`
/// radians around the direction its second input holds: (radians, 1), or (·, 0) for none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DetectMatchAround {
    pub(crate) theta: f32,
    pub(crate) window: u32,
    pub(crate) half_width: f32,
    pub(crate) subpixel: bool,
}

impl DetectMatchAround {
    /// The same pass with the restriction `direction` (a [`super::MeanDirection`]) holds.
    fn with_direction(&self, direction: &Image) -> DetectMatch {
        let known = direction.data.get(1).is_some_and(|&k| k != 0.0);
        let restriction = known.then(|| (direction.data[0], self.half_width));
        let matching = MatchBlocks { window: self.window, restriction, subpixel: self.subpixel };
        DetectMatch { theta: self.theta, matching }
    }
}

impl Unit for DetectMatchAround {
    const NAME: &'static str = "detect_match_around";
    const SOURCE: &'static str = concat!(
        include_str!("detect_match_pixel.wgsl"),
        include_str!("match_search.wgsl"),
        include_str!("motion_measure.wgsl"),
        include_str!("detect_match_around.wgsl")
    );
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(2)];
    const VALUES: &'static [usize] = &[1];
    type Params = super::match_blocks::Params;

    fn params(&self, inputs: &[Shape]) -> Self::Params {
        let matching =
            MatchBlocks { window: self.window, restriction: Some((0.0, self.half_width)), subpixel: self.subpixel };
        matching.params(inputs).with_theta(self.theta)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 2, ..inputs[0] }, Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        Unit::cpu(&self.with_direction(inputs[1]), &inputs[..1])
    }
}
