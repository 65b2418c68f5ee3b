// findIndex: the first index whose value is ≥ threshold, or the length. Pass `main` takes the
// minimum matching index with an atomic (scratch starts at u32::MAX); pass `finish` writes it.
struct Params { len: u32, threshold: f32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> input: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;
@group(0) @binding(3) var<storage, read_write> first: atomic<u32>;

@compute @workgroup_size(256)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * 256u + id.x;
    if i < p.len && input[i] >= p.threshold {
        atomicMin(&first, i);
    }
}

@compute @workgroup_size(1)
fn finish() {
    output[0] = f32(min(atomicLoad(&first), p.len));
}
