//! Fuzz target: any bytes read as a ROS 2 bag (MCAP: summary, chunks, CDR messages, pixels)
//! or as an OpenEXR depth image give images or an error — never a panic, an abort or an
//! allocation past the readers' limits. The first byte chooses the reader.
#![no_main]

use std::path::Path;

use gudsl_formats::{bag, openexr, picture::MAX_PICTURE_PIXELS};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&which, bytes)) = data.split_first() else { return };
    if which % 2 == 0 {
        let _ = bag::images_in_bytes(bytes);
    } else if let Ok((width, height, values)) = openexr::read_depth_bytes(bytes, Path::new("fuzz.exr")) {
        assert!((width as u64) * (height as u64) <= MAX_PICTURE_PIXELS);
        assert_eq!(values.len(), width * height);
    }
});
