// Normals by central differences, facing the camera:
// n = normalise((P(x, y+1) − P(x, y−1)) × (P(x+1, y) − P(x−1, y))); 0 where a neighbour is
// invalid (z = 0) or outside the image.
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> points: array<f32>;
@group(0) @binding(2) var<storage, read_write> normals: array<f32>;

fn at(x: u32, y: u32) -> vec3<f32> {
    let n = p.width * p.height;
    let i = y * p.width + x;
    return vec3<f32>(points[i], points[n + i], points[2u * n + i]);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    var result = vec3<f32>(0.0);
    if id.x > 0u && id.y > 0u && id.x + 1u < p.width && id.y + 1u < p.height {
        let l = at(id.x - 1u, id.y);
        let r = at(id.x + 1u, id.y);
        let u = at(id.x, id.y - 1u);
        let d = at(id.x, id.y + 1u);
        let c = at(id.x, id.y);
        if l.z != 0.0 && r.z != 0.0 && u.z != 0.0 && d.z != 0.0 && c.z != 0.0 {
            let a = d - u;
            let b = r - l;
            let cross_ab = vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
            let len = sqrt(dot(cross_ab, cross_ab));
            if len > 0.0 { result = cross_ab / len; }
        }
    }
    normals[i] = result.x;
    normals[n + i] = result.y;
    normals[2u * n + i] = result.z;
}
