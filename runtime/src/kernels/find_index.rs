//! findIndex (chapter 10): the first index whose value is ≥ a threshold, or the length.

use bytemuck::{Pod, Zeroable};

use crate::kernels::{linear, Scratch};
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `find_index.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    threshold: f32,
    _pad: [u32; 2],
    _pad2: [u32; 4],
}

/// The first index at or above `threshold`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FindIndex {
    pub(crate) threshold: f32,
}

impl Unit for FindIndex {
    const NAME: &'static str = "find_index";
    const SOURCE: &'static str = include_str!("find_index.wgsl");
    const INPUTS: &'static [Option<usize>] = &[None];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        Params { len: inputs[0].len() as u32, threshold: self.threshold, _pad: [0; 2], _pad2: [0; 4] }
    }

    fn outputs(&self, _inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { width: 1, height: 1, planes: 1 }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main(linear(inputs[0].len())), Pass::finish()]
    }

    fn scratch(&self, _inputs: &[Shape]) -> Option<Scratch> {
        Some(Scratch { len: 1, start: u32::MAX })
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![Image::from_plane(1, 1, vec![find_index(&inputs[0].data, self.threshold) as f32])]
    }
}

/// findIndex (chapter 10): the first index whose value is ≥ `threshold`, or `values.len()`.
pub fn find_index(values: &[f32], threshold: f32) -> usize {
    values.iter().position(|&v| v >= threshold).unwrap_or(values.len())
}
