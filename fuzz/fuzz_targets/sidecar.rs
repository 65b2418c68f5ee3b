//! Fuzz target: any text read as a layout sidecar is a layout that writes back to a layout equal
//! to it, or an error — never a panic.
#![no_main]

use gudsl_render::pins::LayoutFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(layout) = LayoutFile::parse(text) {
        let again = LayoutFile::parse(&layout.to_json()).expect("what is written reads back");
        assert_eq!(again, layout);
    }
});
