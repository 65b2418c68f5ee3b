// The findIndex reduction of Listings 34-39 (as samples/seed/listing34_39_find_index.gudsl
// reconstructs them) written by hand: the first index of an element >= the value, -1 for none.
// The model's helpers, one for one: `hits` is bindBetterValueAndReturnNumber, `better`
// findBetterValueIdx, `reduce` reduceFindFirstGreaterOrEqualIdx. `first_stage`: each work-item
// scans its slice of `per_item` elements (keeping the better of its candidate and each element
// until it has one), then the work-group keeps the better candidate of pairs, halving the active
// work-items with a barrier per step, and writes its candidate to `minima[group]`;
// `second_stage`: one work-group reduces the groups' candidates to `last[0]`. A candidate is an
// index or -1; the better of two is the smaller of those whose element is >= the value.
struct Params { count: u32, value: u32, per_item: u32, groups: u32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> elements: array<u32>;
@group(0) @binding(2) var<storage, read_write> minima: array<i32>;
@group(0) @binding(3) var<storage, read_write> last: array<i32>;

override group_size: u32 = 256u;
var<workgroup> best: array<i32, group_size>;

// Which of two values is >= the value: 1 for a, 2 for b, 3 for both, 0 for neither.
fn hits(a: u32, b: u32) -> i32 {
    var number = 0;
    if a >= p.value { number = 1; }
    if b >= p.value { number += 2; }
    return number;
}

fn better(a: i32, b: i32) -> i32 {
    if a < 0 || b < 0 {
        let one = max(a, b);
        if one >= 0 && elements[one] >= p.value { return one; }
        return -1;
    }
    switch hits(elements[a], elements[b]) {
        case 3: { return min(a, b); }
        case 1: { return a; }
        case 2: { return b; }
        default: { return -1; }
    }
}

fn reduce(local: u32) {
    workgroupBarrier();
    for (var stride = group_size / 2u; stride > 0u; stride /= 2u) {
        if local < stride {
            best[local] = better(best[local], best[local + stride]);
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(group_size)
fn first_stage(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) group: vec3<u32>,
) {
    var found = -1;
    let start = i32(id.x * p.per_item);
    let end = min(start + i32(p.per_item), i32(p.count));
    for (var i = start; i < end && found < 0; i++) {
        found = better(found, i);
    }
    best[local] = found;
    reduce(local);
    if local == 0u {
        minima[group.x] = best[0];
    }
}

@compute @workgroup_size(group_size)
fn second_stage(@builtin(local_invocation_index) local: u32) {
    best[local] = -1;
    if local < p.groups {
        best[local] = minima[local];
    }
    reduce(local);
    if local == 0u {
        last[0] = best[0];
    }
}
