//! The kernels' WGSL, without a GPU: every `.wgsl` file under `src/kernels` is some kernel's
//! shader (or shared code prepended to one), every kernel's source parses and validates with naga
//! (the compiler wgpu uses), and every kernel's parameter block is exactly as large as its
//! shader's `Params` struct; so do the hand-written listings (`src/listings`).

use std::path::{Path, PathBuf};

use gudsl_runtime::{Kernel, Shape};

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            wgsl_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            out.push(path);
        }
    }
}

fn module(kernel: &Kernel) -> naga::Module {
    let source = kernel.source();
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{}: {}", kernel.name(), e.emit_to_string(source)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", kernel.name()));
    module
}

#[test]
fn every_shader_file_belongs_to_a_kernel_and_validates() {
    let mut files = Vec::new();
    wgsl_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src/kernels"), &mut files);
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let kernels = Kernel::every_kind();
    let mut names: Vec<&str> = kernels.iter().map(|k| k.name()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), kernels.len(), "two kernels of one name");
    for kernel in &kernels {
        module(kernel);
    }
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        // A kernel's own shader ends its source; shared code (no entry point) starts one.
        let used = if text.contains("@compute") {
            kernels.iter().any(|k| k.source().ends_with(&text))
        } else {
            kernels.iter().any(|k| k.source().starts_with(&text))
        };
        assert!(used, "{} is the shader of no kernel in Kernel::every_kind()", file.display());
    }
}

#[test]
fn every_parameter_block_is_the_size_of_its_shaders_params() {
    // The block's layout does not depend on the images' sizes.
    let image = Shape { width: 64, height: 48, planes: 1 };
    for kernel in Kernel::every_kind() {
        let module = module(&kernel);
        let params = module
            .types
            .iter()
            .find(|(_, ty)| ty.name.as_deref() == Some("Params"))
            .unwrap_or_else(|| panic!("{}: no `Params` struct", kernel.name()));
        let naga::TypeInner::Struct { span, .. } = params.1.inner else {
            panic!("{}: Params is no struct", kernel.name())
        };
        let bytes = kernel.params(&vec![image; kernel.inputs()]).len();
        assert_eq!(bytes, span as usize, "{}: the Rust block is {bytes} bytes, the WGSL Params {span}", kernel.name());
    }
}

#[test]
fn the_listings_shaders_validate_and_their_parameter_blocks_fit() {
    use gudsl_runtime::listings;
    let blocks = [
        (listings::MEAN_WGSL, listings::mean_params(5, 64, 48)),
        (listings::BILATERAL_WGSL, listings::bilateral_params(5.0, 10.0, 50.0, 64, 48)),
    ];
    for (source, block) in blocks {
        let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        let span = module
            .types
            .iter()
            .find_map(|(_, ty)| match &ty.inner {
                naga::TypeInner::Struct { span, .. } if ty.name.as_deref() == Some("Params") => Some(*span),
                _ => None,
            })
            .expect("a Params struct");
        assert_eq!(block.len(), span as usize);
        assert!(module.entry_points.iter().any(|e| e.name == listings::ENTRY_POINT));
    }
}
