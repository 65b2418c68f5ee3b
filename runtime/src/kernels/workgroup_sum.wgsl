// Shared by the reductions (prepended to their source): the sum of one value per thread of a
// 256-thread workgroup, returned to every thread.
var<workgroup> shared_values: array<f32, 256>;

fn reduce_workgroup(t: u32, value: f32) -> f32 {
    shared_values[t] = value;
    workgroupBarrier();
    for (var stride = 128u; stride > 0u; stride = stride / 2u) {
        if t < stride { shared_values[t] += shared_values[t + stride]; }
        workgroupBarrier();
    }
    let total = shared_values[0];
    workgroupBarrier();
    return total;
}
