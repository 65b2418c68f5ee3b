//! `read_image…` through a sampler on the GPU against OpenCL 1.2's definition (8.2, written out
//! here per axis): every addressing mode and filter at normalised and unnormalised float
//! coordinates on a 2D image (the sampler a parameter the host passes), trilinear mirrored
//! reads on a 3D image (the sampler a diagram variable made of `sampler_flags`), integer
//! images at integer and float coordinates; and what cannot be generated.

mod support;

use gudsl_codegen::Kernel;
use gudsl_host::{Arg, Launcher, Number, WorkRange};
use gudsl_runtime::{DeviceBuffer, DeviceImage, Gpu, TexelFormat};
use support::{generated_from, generation};

const NORMALIZED: i32 = 1;
const CLAMP_TO_EDGE: i32 = 2;
const CLAMP: i32 = 4;
const REPEAT: i32 = 6;
const MIRRORED_REPEAT: i32 = 8;
const NEAREST: i32 = 16;
const LINEAR: i32 = 32;

/// A kernel of `params` whose work-item `id` reads `read` (a float4 or int4 expression of the
/// coordinate `at`, made by `coordinate`) and writes its four components to `out`.
fn kernel(params: &str, variables: &str, coordinate: &str, read: &str) -> Kernel {
    let text = format!(
        "ClassDiagram Sampling
{{
    import OpenCL.GPU.*;
    public class Reads implements OpenCL {{ }}
}}

ActivityDiagram reads({params}, global ref float coordinates, global ref float out)
{{
    import OpenCL.GPU.*;
{variables}
    swimlane Device, owner Sampling.Reads
    {{
        start S {{ => work; }}
        action work
        {{
            var int id = get_global_id(0);
            var {coordinate};
            var float4 texel = {read};
            out[4 * id] = texel.x;
            out[4 * id + 1] = texel.y;
            out[4 * id + 2] = texel.z;
            out[4 * id + 3] = texel.w;
            => f;
        }}
        final f;
    }}
}}
"
    );
    generated_from(&[("sampling.gudsl".to_string(), text)], "reads")
}

/// An image of `size` (2 or 3 extents) with distinct texels: texel `(x, y, z)` is
/// `(x + 10y + 100z, 7 - x, y * y, 1)`.
struct Texels {
    size: Vec<i32>,
}

impl Texels {
    fn at(&self, at: &[i32]) -> [f32; 4] {
        let (x, y, z) = (at[0] as f32, at[1] as f32, at.get(2).copied().unwrap_or(0) as f32);
        [x + 10.0 * y + 100.0 * z, 7.0 - x, y * y, 1.0]
    }

    fn all(&self) -> Vec<[f32; 4]> {
        let depth = self.size.get(2).copied().unwrap_or(1);
        let mut out = Vec::new();
        for z in 0..depth {
            for y in 0..self.size[1] {
                for x in 0..self.size[0] {
                    out.push(self.at(&[x, y, z][..self.size.len()]));
                }
            }
        }
        out
    }

    /// OpenCL's read through `sampler` at `coordinate` (8.2.1 nearest, 8.2.2 linear; the
    /// border colour of an RGBA image is 0).
    fn read(&self, sampler: i32, coordinate: &[f32]) -> [f32; 4] {
        let axes: Vec<Axis> = (0..self.size.len()).map(|d| axis(sampler, coordinate[d], self.size[d])).collect();
        let texel = |at: &[i32]| {
            let inside = at.iter().zip(&self.size).all(|(&i, &n)| (0..n).contains(&i));
            if inside {
                self.at(at)
            } else {
                [0.0; 4]
            }
        };
        if sampler & LINEAR == 0 {
            return texel(&axes.iter().map(|a| a.i0).collect::<Vec<_>>());
        }
        let mut sum = [0.0f32; 4];
        for corner in 0..1 << axes.len() {
            let far = |d: usize| corner & (1 << d) != 0;
            let at: Vec<i32> = (0..axes.len()).map(|d| if far(d) { axes[d].i1 } else { axes[d].i0 }).collect();
            let weight: f32 = (0..axes.len()).map(|d| if far(d) { axes[d].a } else { 1.0 - axes[d].a }).product();
            for (s, t) in sum.iter_mut().zip(texel(&at)) {
                *s += weight * t;
            }
        }
        sum
    }
}

/// One axis of a read: the texel (nearest: `i0`) or the two texels and the weight of the second
/// (linear).
struct Axis {
    i0: i32,
    i1: i32,
    a: f32,
}

fn axis(sampler: i32, coordinate: f32, size: i32) -> Axis {
    let width = size as f32;
    let linear = sampler & LINEAR != 0;
    let frac = |v: f32| v - v.floor();
    match sampler & 0b1110 {
        REPEAT => {
            let s = coordinate;
            let u = (s - s.floor()) * width;
            if !linear {
                let i = u.floor() as i32;
                return Axis { i0: if i > size - 1 { i - size } else { i }, i1: 0, a: 0.0 };
            }
            let i0 = (u - 0.5).floor() as i32;
            let i1 = i0 + 1;
            Axis {
                i0: if i0 < 0 { size + i0 } else { i0 },
                i1: if i1 > size - 1 { i1 - size } else { i1 },
                a: frac(u - 0.5),
            }
        }
        MIRRORED_REPEAT => {
            let s = coordinate;
            let u = (s - 2.0 * (0.5 * s).round_ties_even()).abs() * width;
            if !linear {
                return Axis { i0: (u.floor() as i32).min(size - 1), i1: 0, a: 0.0 };
            }
            let i0 = (u - 0.5).floor() as i32;
            Axis { i0: i0.max(0), i1: (i0 + 1).min(size - 1), a: frac(u - 0.5) }
        }
        mode => {
            let u = if sampler & NORMALIZED != 0 { coordinate * width } else { coordinate };
            // CLK_ADDRESS_CLAMP leaves the texel outside (the border colour), the others clamp.
            let address = |i: i32| if mode == CLAMP { i.clamp(-1, size) } else { i.clamp(0, size - 1) };
            match linear {
                false => Axis { i0: address(u.floor() as i32), i1: 0, a: 0.0 },
                true => {
                    let i0 = (u - 0.5).floor() as i32;
                    Axis { i0: address(i0), i1: address(i0 + 1), a: frac(u - 0.5) }
                }
            }
        }
    }
}

/// Coordinates across and well outside the image, at least 1/8 texel from texel edges (where
/// nearest reads would depend on the last bit of a division); then the exact edges that the
/// products compute exactly (image borders, the middle, whole repeats).
fn coordinates(count: usize, size: &[i32], normalized: bool, seed: u64) -> Vec<Vec<f32>> {
    let exact: &[f32] = if normalized { &[0.0, 0.5, 1.0, -1.0, 2.0, 3.0] } else { &[0.0, 1.0, -1.0, 2.5] };
    let edges = exact.iter().map(|&c| vec![c; size.len()]);
    let bytes = support::random_bytes(count * size.len(), seed);
    let mut all: Vec<Vec<f32>> = bytes
        .chunks(size.len())
        .map(|chunk| {
            chunk
                .iter()
                .zip(size)
                .map(|(&b, &n)| {
                    let texels = (b as f32 / 255.0) * (5.0 * n as f32) - 2.0 * n as f32;
                    let u = texels.floor() + 0.125 + 0.75 * texels.fract();
                    if normalized {
                        u / n as f32
                    } else {
                        u
                    }
                })
                .collect()
        })
        .collect();
    all.extend(edges);
    if !normalized {
        all.extend(size.iter().map(|&n| vec![n as f32; size.len()]));
    }
    all
}

/// Runs a `kernel(...)` kernel over the coordinates with `first` (the image) and `sampler` (when
/// it is a parameter) as its first arguments; the texels it read.
fn run(gpu: &Gpu, kernel: &Kernel, image: &DeviceImage, sampler: Option<i32>, at: &[Vec<f32>]) -> Vec<[f32; 4]> {
    let launcher = Launcher::new(gpu, kernel).unwrap();
    let flat: Vec<u8> = at.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let coordinates = DeviceBuffer::new(gpu, "coordinates", flat.len() as u64).unwrap();
    coordinates.write(gpu, &flat).unwrap();
    let out = DeviceBuffer::new(gpu, "out", 16 * at.len() as u64).unwrap();
    let mut args = vec![Arg::Image(image)];
    args.extend(sampler.map(|s| Arg::Number(Number::Int(s.into()))));
    args.extend([Arg::Buffer(&coordinates), Arg::Buffer(&out)]);
    launcher.launch(gpu, &args, &WorkRange::linear(at.len() as u32, None)).unwrap();
    let floats: Vec<f32> =
        out.read(gpu).unwrap().chunks(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect();
    floats.chunks(4).map(|c| c.try_into().unwrap()).collect()
}

fn upload_float(gpu: &Gpu, texels: &Texels) -> DeviceImage {
    let size = [texels.size[0] as u32, texels.size[1] as u32, texels.size.get(2).copied().unwrap_or(1) as u32];
    let image = DeviceImage::new(gpu, "image", TexelFormat::Rgba32Float, texels.size.len() as u8, size).unwrap();
    let bytes: Vec<u8> = texels.all().iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    image.write(gpu, &bytes).unwrap();
    image
}

/// Where the GPU's texels differ from the reference's by more than a filter's rounding.
fn compare(label: &str, got: &[[f32; 4]], want: impl Fn(usize) -> [f32; 4], at: &[Vec<f32>]) {
    for (i, got) in got.iter().enumerate() {
        let want = want(i);
        let close = got.iter().zip(want).all(|(g, w)| (g - w).abs() <= 1e-3 * w.abs().max(1.0));
        assert!(close, "{label}: at {:?} the GPU read {got:?}, OpenCL reads {want:?}", at[i]);
    }
}

#[test]
fn float_coordinates_read_as_opencl_samplers_do_in_every_mode() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let texels = Texels { size: vec![5, 3] };
    let image = upload_float(&gpu, &texels);
    let kernel = kernel(
        "image2D_f picture, sampler_t smp",
        "",
        "float2 at = new float2(coordinates[2 * id], coordinates[2 * id + 1])",
        "read_imagef(picture, smp, at)",
    );
    let mut samplers = Vec::new();
    for filter in [NEAREST, LINEAR] {
        for normalized in [0, NORMALIZED] {
            for address in [0, CLAMP_TO_EDGE, CLAMP] {
                samplers.push(normalized | address | filter);
            }
        }
        // Repeat and mirrored repeat are defined for normalised coordinates only.
        samplers.extend([NORMALIZED | REPEAT | filter, NORMALIZED | MIRRORED_REPEAT | filter]);
    }
    for (n, sampler) in samplers.into_iter().enumerate() {
        let at = coordinates(96, &texels.size, sampler & NORMALIZED != 0, 11 + n as u64);
        let got = run(&gpu, &kernel, &image, Some(sampler), &at);
        compare(&format!("sampler {sampler:#x}"), &got, |i| texels.read(sampler, &at[i]), &at);
    }
}

#[test]
fn a_sampler_made_of_flags_in_the_diagram_reads_a_3d_image_trilinearly() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let texels = Texels { size: vec![3, 4, 2] };
    let image = upload_float(&gpu, &texels);
    let kernel = kernel(
        "image3D_f volume",
        "    public sampler_t mirrored = sampler_flags.CLK_NORMALIZED_COORDS_TRUE\n        | sampler_flags.CLK_ADDRESS_MIRRORED_REPEAT | sampler_flags.CLK_FILTER_LINEAR;",
        "float4 at = new float4(coordinates[3 * id], coordinates[3 * id + 1], coordinates[3 * id + 2], 0.0f)",
        "read_imagef(volume, mirrored, at)",
    );
    assert!(kernel.wgsl.contains("(1i | 8i) | 32i"), "the flags are OpenCL's values:\n{}", kernel.wgsl);
    let at = coordinates(128, &texels.size, true, 5);
    let got = run(&gpu, &kernel, &image, None, &at);
    compare("3D", &got, |i| texels.read(NORMALIZED | MIRRORED_REPEAT | LINEAR, &at[i]), &at);
}

#[test]
fn integer_images_read_the_border_colour_only_through_a_clamping_sampler() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let texels = Texels { size: vec![4, 4] };
    let image = DeviceImage::new(&gpu, "image", TexelFormat::Rgba32Sint, 2, [4, 4, 1]).unwrap();
    let bytes: Vec<u8> = texels.all().iter().flatten().flat_map(|&v| (v as i32).to_le_bytes()).collect();
    image.write(&gpu, &bytes).unwrap();
    let grid: Vec<Vec<f32>> = (-2..6).flat_map(|y| (-2..6).map(move |x| vec![x as f32, y as f32])).collect();
    let integer_at = "int2 at = new int2((int)coordinates[2 * id], (int)coordinates[2 * id + 1])";
    // Integer coordinates: no sampler and CLK_ADDRESS_CLAMP_TO_EDGE clamp to the edge,
    // CLK_ADDRESS_CLAMP gives the border, CLK_ADDRESS_NONE reads inside the image (outside,
    // OpenCL leaves it undefined).
    let inside: Vec<Vec<f32>> = grid.iter().filter(|at| at.iter().all(|&c| (0.0..4.0).contains(&c))).cloned().collect();
    for (read, sampler, at) in [
        ("read_imagei(picture, at)", None, &grid),
        ("read_imagei(picture, smp, at)", Some(CLAMP), &grid),
        ("read_imagei(picture, smp, at)", Some(CLAMP_TO_EDGE), &grid),
        ("read_imagei(picture, smp, at)", Some(0), &inside),
    ] {
        let params = if sampler.is_some() { "image2D_i picture, sampler_t smp" } else { "image2D_i picture" };
        let kernel = kernel(params, "", integer_at, read);
        let got = run(&gpu, &kernel, &image, sampler, at);
        let flags = sampler.unwrap_or(CLAMP_TO_EDGE) | NEAREST;
        compare(&format!("{read} with {sampler:?}"), &got, |i| texels.read(flags, &at[i]), at);
    }
    // Float coordinates on an integer image: the nearest texel.
    let kernel = kernel(
        "image2D_i picture, sampler_t smp",
        "",
        "float2 at = new float2(coordinates[2 * id], coordinates[2 * id + 1])",
        "read_imagei(picture, smp, at)",
    );
    let at = coordinates(64, &texels.size, true, 3);
    let sampler = NORMALIZED | REPEAT | NEAREST;
    let got = run(&gpu, &kernel, &image, Some(sampler), &at);
    compare("read_imagei at float coordinates", &got, |i| texels.read(sampler, &at[i]), &at);
}

#[test]
fn a_float_coordinate_without_a_sampler_is_an_error_at_the_read() {
    let text = "ClassDiagram Sampling { import OpenCL.GPU.*; public class Reads implements OpenCL { } }
ActivityDiagram reads(image2D_f picture, global ref float out)
{
    import OpenCL.GPU.*;
    swimlane Device, owner Sampling.Reads
    {
        start S { => work; }
        action work
        {
            var float4 texel = read_imagef(picture, new float2(0.5f, 0.5f));
            out[0] = texel.x;
            => f;
        }
        final f;
    }
}
";
    let errors = generation(&[("sampling.gudsl".into(), text.into())], "reads").unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].1, 10);
    assert!(errors[0].2.contains("goes through a sampler"), "{errors:?}");
}
