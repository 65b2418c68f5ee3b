//! Writes the sample image `Main` loads (`samples/seed/tof_amplitude.png`): the amplitude of
//! one frame of the runtime's simulated PMD camera — chapter 4's turned box at about 3 m before
//! a wall at 4 m, on a 512×512 sensor with the CamCube's optics, photon and read noise
//! included — as 8-bit grey levels (the brightest pixel 255).
//!
//! `cargo run -p gudsl-host --example tof_image -- samples/seed/tof_amplitude.png`

use gudsl_runtime::{
    camera::Intrinsics,
    kernels::tof,
    sim::{simulate, Camera, Motion, Scene},
};

const SIZE: usize = 512;

fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| "tof_amplitude.png".into());
    let scale = SIZE as f32 / Intrinsics::CAMCUBE.width as f32;
    let c = Intrinsics::CAMCUBE;
    let intrinsics = Intrinsics {
        width: SIZE,
        height: SIZE,
        fx: c.fx * scale,
        fy: c.fy * scale,
        cx: c.cx * scale,
        cy: c.cy * scale,
        ..c
    };
    let camera = Camera { intrinsics, supersampling: 1, ..Camera::default() };
    let frame = simulate(&Scene::turned_box(), Motion::Still, &camera, 0);
    let raw = tof::subtract_black(&frame.raw, &frame.black);
    let [_, amplitude, _, _] = tof::demodulate(&raw, camera.modulation_hz);
    let brightest = amplitude.data.iter().copied().fold(0.0f32, f32::max);
    let grey: Vec<u8> = amplitude.data.iter().map(|&a| (a / brightest * 255.0).round() as u8).collect();
    image::save_buffer(&path, &grey, SIZE as u32, SIZE as u32, image::ExtendedColorType::L8)
        .expect("the image is written");
    println!("wrote {path} ({SIZE}×{SIZE}, simulated ToF amplitude)");
}
