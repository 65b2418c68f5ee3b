//! ToF pipeline runtime (WGSL kernels on wgpu, CPU reference, camera simulator); built in a later issue.
