//! Frames in flight: the executor submits frame n+1 before frame n's reads are collected
//! (`submit_frame`, `collect`). Each frame's reads are its own — though every frame uploads
//! into the same buffer and runs the same kernel into the same output — and so are its
//! timestamps; on the CPU reference the same calls give the same.

use std::collections::VecDeque;

use gudsl_runtime::{
    executor::{BufferSlot, KernelSlot},
    Executor, Gpu, Image, Kernel,
};

/// Frame `k`'s input: a ramp of its own.
fn input(k: usize) -> Image {
    let data = (0..64 * 48).map(|i| ((i * (k + 3)) % 251) as f32).collect();
    Image { width: 64, height: 48, planes: 1, data }
}

/// Three frames submitted before the first is collected; each collected frame's read compared
/// with the kernel's CPU reference on that frame's input.
fn three_frames_in_flight(gpu: Option<&Gpu>) {
    let kernel = Kernel::Mean { radius: 2 };
    let mut executor = Executor::new(gpu);
    let (mut upload, mut slot) = (BufferSlot::default(), KernelSlot::default());
    let mut in_flight = VecDeque::new();
    for k in 0..3 {
        assert_eq!(executor.recording(), k as u64);
        let uploaded = executor.upload(&mut upload, &input(k));
        let mean = executor.kernel(k, &mut slot, kernel, &[&uploaded]).unwrap().remove(0);
        let later = executor.read_later(&mean);
        in_flight.push_back((later, executor.submit_frame().unwrap()));
    }
    for k in 0..3 {
        let (later, frame) = in_flight.pop_front().unwrap();
        let (reads, times) = executor.collect(frame).unwrap();
        assert_eq!(reads.recording(), k as u64);
        let expected = kernel.cpu(&[&input(k)]).remove(0);
        let worst = reads.get(later).data.iter().zip(&expected.data).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(worst < 1e-3, "frame {k}: off by {worst} from its own input's mean");
        // Its one pass, timed under its own stage (the timestamps came back in its mapping).
        let stages: Vec<usize> = times.iter().map(|(stage, _)| *stage).collect();
        let timed = gpu.is_some_and(Gpu::times_on_device);
        assert_eq!(stages, if timed { vec![k] } else { vec![] }, "frame {k}'s timed passes");
    }
    let work = executor.take_work();
    assert_eq!(work.submissions, if gpu.is_some() { 3 } else { 0 });
}

#[test]
fn each_frame_in_flight_reads_its_own_results_on_the_gpu() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let gpu = Gpu::with_timestamps().expect("an adapter, as for_tests found");
    three_frames_in_flight(Some(&gpu));
}

#[test]
fn each_frame_in_flight_reads_its_own_results_on_the_cpu_reference() {
    three_frames_in_flight(None);
}
