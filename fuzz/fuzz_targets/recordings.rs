//! Fuzz target: any bytes read as a ROS 2 bag (MCAP: summary, chunks, CDR messages, pixels and
//! points), an OpenEXR depth image or a PCD point cloud give what they hold or an error —
//! never a panic, an abort or an allocation past the readers' limits. The first byte chooses
//! the reader.
#![no_main]

use std::path::Path;

use gudsl_formats::{bag, openexr, pcd, picture::MAX_PICTURE_PIXELS};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&which, bytes)) = data.split_first() else { return };
    if which % 3 == 0 {
        let _ = bag::contents_in_bytes(bytes);
    } else if which % 3 == 2 {
        if let Ok((points, normals)) = pcd::read_bytes(bytes, Path::new("fuzz.pcd")) {
            assert_eq!(points.len(), normals.len());
        }
    } else if let Ok((width, height, values)) = openexr::read_depth_bytes(bytes, Path::new("fuzz.exr")) {
        assert!((width as u64) * (height as u64) <= MAX_PICTURE_PIXELS);
        assert_eq!(values.len(), width * height);
    }
});
