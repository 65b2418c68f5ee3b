// Rigid transform of a point cloud: every valid point (z ≠ 0) moved by the pose [R | t].
struct Params { pose0: vec4<f32>, pose1: vec4<f32>, pose2: vec4<f32>, size: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> points: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let width = p.size.x;
    let n = p.size.x * p.size.y;
    let i = id.y * width + id.x;
    if id.x >= width || i >= n { return; }
    let v = vec3<f32>(points[i], points[n + i], points[2u * n + i]);
    var q = vec3<f32>(0.0);
    if v.z != 0.0 {
        let h = vec4<f32>(v, 1.0);
        q = vec3<f32>(dot(p.pose0, h), dot(p.pose1, h), dot(p.pose2, h));
    }
    output[i] = q.x;
    output[n + i] = q.y;
    output[2u * n + i] = q.z;
}
