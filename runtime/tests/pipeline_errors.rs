//! A pipeline given the wrong images answers with an error that says what is wrong, at the step
//! that is wrong or at the run; nothing panics. No GPU needed.

use gudsl_runtime::{run_cpu, ChainError, Image, Kernel, Pipeline, Shape, Slot};

fn plane(width: usize, height: usize) -> Shape {
    Shape { width, height, planes: 1 }
}

#[test]
fn a_step_of_the_wrong_images_is_an_error() {
    let mut p = Pipeline::new();
    let raw = p.source("raw", Shape { width: 8, height: 6, planes: 8 });
    let distance = p.source("distance", plane(8, 6));
    let small = p.source("small", plane(4, 3));
    assert_eq!(
        p.step(Kernel::SubtractBlack, &[raw]),
        Err(ChainError::Inputs { kernel: "subtract_black", expected: 2, given: 1 })
    );
    assert_eq!(
        p.step(Kernel::Demodulate { modulation_hz: 20e6 }, &[distance]),
        Err(ChainError::Planes { kernel: "demodulate", input: 0, expected: 8, given: 1 })
    );
    let error = p.step(Kernel::ApplyMask, &[distance, small]).unwrap_err();
    assert_eq!(error, ChainError::Size { kernel: "apply_mask", input: 1, expected: (8, 6), given: (4, 3) });
    assert!(error.to_string().contains("input 1 of kernel `apply_mask` is 4×3"), "{error}");
    assert_eq!(p.step(Kernel::Mean { radius: 1 }, &[Slot(99)]), Err(ChainError::UnknownSlot(99)));
    assert_eq!(p.sink(Slot(99)), Err(ChainError::UnknownSlot(99)));
    let empty = p.source("empty", plane(0, 0));
    assert!(matches!(p.step(Kernel::Mean { radius: 1 }, &[empty]), Err(ChainError::Size { .. })));
    // Nothing was added by the failed steps.
    assert!(p.steps.is_empty());
}

#[test]
fn a_run_of_the_wrong_sources_is_an_error() {
    let mut p = Pipeline::new();
    let input = p.source("input", plane(8, 6));
    let out = p.step(Kernel::Mean { radius: 1 }, &[input]).unwrap()[0];
    p.sink(out).unwrap();
    assert_eq!(run_cpu(&p, &[]), Err(ChainError::Sources { expected: 1, given: 0 }));
    let wrong = Image::zeros(6, 8, 1);
    let error = run_cpu(&p, &[wrong]).unwrap_err();
    assert!(matches!(error, ChainError::SourceShape { ref source, .. } if source == "input"), "{error}");
    assert!(error.to_string().contains("must be 8×6×1"), "{error}");
    assert_eq!(run_cpu(&p, &[Image::zeros(8, 6, 1)]).unwrap()[0], Image::zeros(8, 6, 1));
}
