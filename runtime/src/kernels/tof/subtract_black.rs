//! Black-image subtraction (sec. 2.1.2): the chip's fixed-pattern offset taken off every raw
//! sample.

use bytemuck::{Pod, Zeroable};

use crate::kernels::linear;
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `subtract_black.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    _pad: u32,
    _pad1: [u32; 2],
    _pad2: [u32; 4],
}

/// Raw frame, black frame → raw frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SubtractBlack;

impl Unit for SubtractBlack {
    const NAME: &'static str = "subtract_black";
    const SOURCE: &'static str = concat!(include_str!("less_black.wgsl"), include_str!("subtract_black.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(8)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        Params { len: inputs[0].len() as u32, _pad: 0, _pad1: [0; 2], _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![inputs[0]]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main(linear(inputs[0].len()))]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![subtract_black(inputs[0], inputs[1])]
    }
}

/// Fixed-pattern-noise removal (sec. 2.1.2): the chip's black image subtracted from every raw
/// plane, clamped at 0.
pub fn subtract_black(raw: &Image, black: &Image) -> Image {
    let data = raw.data.iter().zip(&black.data).map(|(r, b)| (r - b).max(0.0)).collect();
    Image { data, ..raw.clone() }
}
