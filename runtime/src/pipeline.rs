//! A pipeline: named source images, kernel steps between image slots, and the sinks to read.
//! Shapes flow from the sources through each kernel, so a pipeline is checked when it is built:
//! a step given the wrong images is an error, not a panic later.

use crate::{
    error::ChainError,
    kernels::{Kernel, Shape},
};

/// An image slot of a pipeline (a source or a step's output).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Slot(pub usize);

/// One kernel run: its inputs and outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub kernel: Kernel,
    pub inputs: Vec<Slot>,
    pub outputs: Vec<Slot>,
}

/// Sources, steps in execution order, and sinks.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pipeline {
    /// Shape and name of every slot.
    pub slots: Vec<(String, Shape)>,
    pub sources: Vec<Slot>,
    pub steps: Vec<Step>,
    pub sinks: Vec<Slot>,
}

impl Pipeline {
    pub fn new() -> Pipeline {
        Pipeline::default()
    }

    /// A source image the caller provides each run.
    pub fn source(&mut self, name: &str, shape: Shape) -> Slot {
        let slot = self.slot(name, shape);
        self.sources.push(slot);
        slot
    }

    fn slot(&mut self, name: &str, shape: Shape) -> Slot {
        self.slots.push((name.to_string(), shape));
        Slot(self.slots.len() - 1)
    }

    /// The shape of a slot.
    pub fn shape(&self, slot: Slot) -> Shape {
        self.slots[slot.0].1
    }

    /// Runs `kernel` on `inputs`; returns its output slots, or why the inputs do not fit it.
    pub fn step(&mut self, kernel: Kernel, inputs: &[Slot]) -> Result<Vec<Slot>, ChainError> {
        let shapes = inputs
            .iter()
            .map(|s| self.slots.get(s.0).map(|(_, shape)| *shape).ok_or(ChainError::UnknownSlot(s.0)))
            .collect::<Result<Vec<Shape>, _>>()?;
        kernel.check(&shapes)?;
        let outputs: Vec<Slot> = kernel
            .outputs(&shapes)
            .into_iter()
            .enumerate()
            .map(|(i, shape)| self.slot(&format!("{}#{}.{i}", kernel.name(), self.steps.len()), shape))
            .collect();
        self.steps.push(Step { kernel, inputs: inputs.to_vec(), outputs: outputs.clone() });
        Ok(outputs)
    }

    /// Reads `slot` back after each run.
    pub fn sink(&mut self, slot: Slot) -> Result<(), ChainError> {
        if slot.0 >= self.slots.len() {
            return Err(ChainError::UnknownSlot(slot.0));
        }
        self.sinks.push(slot);
        Ok(())
    }

    /// Checks that `sources` fit the pipeline's sources, one image each of the shape it was
    /// built for.
    pub fn check_sources(&self, sources: &[crate::Image]) -> Result<(), ChainError> {
        if sources.len() != self.sources.len() {
            return Err(ChainError::Sources { expected: self.sources.len(), given: sources.len() });
        }
        for (&slot, image) in self.sources.iter().zip(sources) {
            let (name, expected) = &self.slots[slot.0];
            let given = Shape { width: image.width, height: image.height, planes: image.planes };
            if given != *expected || image.data.len() != expected.len() {
                return Err(ChainError::SourceShape { source: name.clone(), expected: *expected, given });
            }
        }
        Ok(())
    }
}
