//! Fuzz target: any bytes read as a `.npy` file give an array whose values fill its shape, or an
//! error naming the file — never a panic, an abort or an allocation the bytes do not justify.
#![no_main]

use std::path::Path;

use gudsl_formats::arrays;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(array) = arrays::read_bytes(data, Path::new("fuzz.npy")) {
        assert_eq!(array.values.len(), array.shape.iter().product::<usize>());
    }
});
