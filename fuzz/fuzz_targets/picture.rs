//! Fuzz target: any bytes read as a PNG or JPEG picture decode to an image of the size its
//! header gave, within the pixel cap, or an error — never a panic, an abort or an allocation
//! past the decoder's limit.
#![no_main]

use std::path::Path;

use gudsl_formats::picture;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(image) = picture::decode_bytes(data, Path::new("fuzz.png")) {
        assert!(u64::from(image.width()) * u64::from(image.height()) <= picture::MAX_PICTURE_PIXELS);
    }
});
