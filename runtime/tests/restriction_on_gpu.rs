//! ρ on the GPU (chapter 4's direction restriction): the mean direction of a frame's flow
//! (`Kernel::MeanDirection`) is computed where the flow is, and the next frame's search
//! (`Kernel::DetectMatchAround`) reads it there — no read back between frames. The direction
//! agrees with its CPU twin and the host's circular mean; while nothing moved (or the vectors
//! cancel) it is the one before; the search around a direction in a buffer is exactly the fused pass with that
//! direction as a parameter.

use std::f32::consts::FRAC_PI_4;

use gudsl_runtime::kernels::motion::mean_direction;
use gudsl_runtime::sim::{simulate, Camera, Motion, Scene};
use gudsl_runtime::{run_cpu, ChainRun, Gpu, Image, Kernel, Pipeline, Shape};

/// `kernel` on `inputs` by the CPU reference and on `gpu`: every output of each.
fn both(gpu: &Gpu, kernel: Kernel, inputs: &[Image]) -> (Vec<Image>, Vec<Image>) {
    let mut pipeline = Pipeline::new();
    let sources: Vec<_> = (inputs.iter().enumerate())
        .map(|(i, im)| {
            pipeline.source(&format!("in{i}"), Shape { width: im.width, height: im.height, planes: im.planes })
        })
        .collect();
    for slot in pipeline.step(kernel, &sources).unwrap() {
        pipeline.sink(slot).unwrap();
    }
    (run_cpu(&pipeline, inputs).unwrap(), ChainRun::new(Some(gpu), &pipeline).run(inputs).unwrap())
}

/// A direction value: (radians, 1), or none known.
fn direction(radians: Option<f32>) -> Image {
    let data = radians.map_or(vec![0.0, 0.0], |r| vec![r, 1.0]);
    Image { width: 1, height: 1, planes: 2, data }
}

/// A raw frame of a scene moving sideways, black image subtracted.
fn moving_frame() -> Image {
    let frame = simulate(&Scene::height_field(), Motion::Translation([0.02, 0.01, 0.0]), &Camera::default(), 0);
    gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black)
}

#[test]
fn a_flow_s_mean_direction_is_computed_on_the_gpu_or_kept_while_nothing_moved() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let theta = 655.0;
    let search = Kernel::DetectMatch { theta, window: 5, restriction: None, subpixel: true };
    let flow = search.cpu(&[&moving_frame()]).remove(0);
    let (cpu, on_gpu) = both(&gpu, Kernel::MeanDirection, &[flow.clone(), direction(None)]);
    let host = mean_direction(&flow).expect("the scene moves");
    assert_eq!(cpu[0].data[1], 1.0);
    assert!((cpu[0].data[0] - host).abs() < 1e-4, "twin {} vs host {host}", cpu[0].data[0]);
    assert_eq!(on_gpu[0].data[1], 1.0);
    assert!((on_gpu[0].data[0] - cpu[0].data[0]).abs() < 1e-5, "GPU {:?} vs CPU {:?}", on_gpu[0].data, cpu[0].data);
    let still = Image { data: vec![0.0; flow.data.len()], ..flow.clone() };
    // As many vectors to the left as to the right: they cancel, and have no direction either.
    let n = flow.pixels();
    let mut cancelling = still.clone();
    (0..n).for_each(|i| cancelling.data[i] = if i % 2 == 0 { 1.0 } else { -1.0 });
    for before in [direction(None), direction(Some(2.5))] {
        for (what, flow) in [("nothing moved", &still), ("the vectors cancel", &cancelling)] {
            let (cpu, on_gpu) = both(&gpu, Kernel::MeanDirection, &[flow.clone(), before.clone()]);
            assert_eq!((&cpu[0].data, &on_gpu[0].data), (&before.data, &before.data), "{what}");
        }
    }
}

#[test]
fn the_search_around_a_direction_in_a_buffer_is_the_search_around_that_parameter() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let raw = moving_frame();
    let theta = 655.0;
    for around in [None, Some(0.4), Some(3.5)] {
        for (window, subpixel) in [(5, false), (7, true)] {
            let restriction = around.map(|radians| (radians, FRAC_PI_4));
            let fixed = Kernel::DetectMatch { theta, window, restriction, subpixel };
            let buffered = Kernel::DetectMatchAround { theta, window, half_width: FRAC_PI_4, subpixel };
            let (fixed_cpu, fixed_gpu) = both(&gpu, fixed, std::slice::from_ref(&raw));
            let (buffered_cpu, buffered_gpu) = both(&gpu, buffered, &[raw.clone(), direction(around)]);
            let what = format!("around {around:?}, window {window}, subpixel {subpixel}");
            assert!(fixed_gpu[1].data.iter().filter(|&&m| m == 1.0).count() > 1000, "moving pixels");
            for k in 0..2 {
                assert_eq!(fixed_gpu[k].data, buffered_gpu[k].data, "{what}: output {k} on the GPU");
                assert_eq!(fixed_cpu[k].data, buffered_cpu[k].data, "{what}: output {k} on the CPU");
            }
        }
    }
}

/// A direction is one value: a buffer of another size is refused where the chain is built.
#[test]
fn a_direction_of_the_image_s_size_is_refused() {
    let mut pipeline = Pipeline::new();
    let flow = pipeline.source("flow", Shape { width: 64, height: 48, planes: 2 });
    let wrong = pipeline.source("before", Shape { width: 64, height: 48, planes: 2 });
    let refused = pipeline.step(Kernel::MeanDirection, &[flow, wrong]).unwrap_err().to_string();
    assert!(refused.contains("1×1") || refused.contains("(1, 1)"), "{refused}");
}
