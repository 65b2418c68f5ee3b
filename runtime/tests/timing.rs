//! The GPU's clock times every kernel of a frame, however many the frame has: a chain of 100
//! steps gets a time for each step in its first frame (each step has work to time).

use gudsl_runtime::{ChainRun, Gpu, Image, Kernel, Pipeline, Shape};

#[test]
fn every_step_of_a_long_chain_is_timed_in_the_first_frame() {
    let Ok(gpu) = Gpu::with_timestamps() else { return };
    if !gpu.times_on_device() {
        eprintln!("skipped: {} has no timestamp queries", gpu.describe());
        return;
    }
    let shape = Shape { width: 256, height: 256, planes: 1 };
    let mut pipeline = Pipeline::new();
    let mut slot = pipeline.source("in", shape);
    for _ in 0..100 {
        slot = pipeline.step(Kernel::Mean { radius: 2 }, &[slot]).unwrap()[0];
    }
    pipeline.sink(slot).unwrap();
    let image = Image { width: 256, height: 256, planes: 1, data: (0..256 * 256).map(|i| (i % 97) as f32).collect() };
    let times = ChainRun::new(Some(&gpu), &pipeline).time_steps(&[image]).unwrap();
    assert_eq!(times.len(), 100);
    let untimed: Vec<usize> = (0..times.len()).filter(|&k| times[k].is_zero()).collect();
    assert!(untimed.is_empty(), "steps without a time: {untimed:?} of {times:?}");
}
