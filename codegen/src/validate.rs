//! Every generated module through naga, the shader compiler wgpu uses: parsed and validated
//! (types, uniformity rules naga checks, bindings) before anyone runs it.

use naga::valid::{Capabilities, ValidationFlags, Validator};

/// `Ok` if `wgsl` is a valid module; naga's message otherwise.
pub(crate) fn validate(wgsl: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| e.emit_to_string(wgsl))?;
    Ok(module)
}
