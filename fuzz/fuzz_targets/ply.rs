//! Fuzz target: any bytes read as a PLY file give as many normals as points, or an error —
//! never a panic or an abort.
#![no_main]

use gudsl_formats::ply;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((points, normals)) = ply::read(data) {
        assert_eq!(points.len(), normals.len());
    }
});
