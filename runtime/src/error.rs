//! What can go wrong building or running a chain of kernels on the executor ([`ChainError`]; a
//! ToF pipeline of `gudsl run` has `gudsl_host`'s `PipelineError`): every case is a value with a
//! message a user can act on, never a panic.

use std::fmt;

use crate::image::Shape;

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ChainError {
    /// A kernel given another number of inputs than it reads.
    Inputs { kernel: &'static str, expected: usize, given: usize },
    /// An input with another number of planes than the kernel reads.
    Planes { kernel: &'static str, input: usize, expected: usize, given: usize },
    /// An input of another size than the kernel's first input (or of no size at all).
    Size { kernel: &'static str, input: usize, expected: (usize, usize), given: (usize, usize) },
    /// A slot that is not in the pipeline.
    UnknownSlot(usize),
    /// Another number of source images than the pipeline has sources.
    Sources { expected: usize, given: usize },
    /// A source image of another shape than the pipeline was built for.
    SourceShape { source: String, expected: Shape, given: Shape },
    /// No step of that index.
    UnknownStep(usize),
    /// A step's kernel replaced by another kind of kernel (only parameters may change).
    KernelChanged { step: usize, was: &'static str, given: &'static str },
    /// The GPU did not hand the results back.
    Readback(String),
}

fn shape(s: &Shape) -> String {
    format!("{}×{}×{}", s.width, s.height, s.planes)
}

impl fmt::Display for ChainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChainError::Inputs { kernel, expected, given } => {
                write!(f, "kernel `{kernel}` reads {expected} input image(s), {given} given")
            }
            ChainError::Planes { kernel, input, expected, given } => {
                write!(f, "input {input} of kernel `{kernel}` needs {expected} plane(s), it has {given}")
            }
            ChainError::Size { kernel, input, expected, given } => write!(
                f,
                "input {input} of kernel `{kernel}` is {}×{}, but its images must all be {}×{} (and not empty)",
                given.0, given.1, expected.0, expected.1
            ),
            ChainError::UnknownSlot(slot) => write!(f, "slot {slot} is not an image of this pipeline"),
            ChainError::Sources { expected, given } => {
                write!(f, "the pipeline takes {expected} source image(s), {given} given")
            }
            ChainError::SourceShape { source, expected, given } => {
                write!(f, "source `{source}` must be {} (width×height×planes), it is {}", shape(expected), shape(given))
            }
            ChainError::UnknownStep(step) => write!(f, "the pipeline has no step {step}"),
            ChainError::KernelChanged { step, was, given } => {
                write!(f, "step {step} runs `{was}`; only its parameters can change, not the kernel (`{given}` given)")
            }
            ChainError::Readback(message) => write!(f, "the GPU did not return the results: {message}"),
        }
    }
}

impl std::error::Error for ChainError {}
