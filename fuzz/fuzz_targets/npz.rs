//! Fuzz target: any bytes read as a `.npz` archive (its only array, or the member `a`) give an
//! array whose values fill its shape, or an error naming the archive — never a panic or an abort.
#![no_main]

use std::path::Path;

use gudsl_formats::arrays;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for name in ["fuzz.npz", "fuzz.npz:a"] {
        if let Ok(array) = arrays::read_bytes(data, Path::new(name)) {
            assert_eq!(array.values.len(), array.shape.iter().product::<usize>());
        }
    }
});
