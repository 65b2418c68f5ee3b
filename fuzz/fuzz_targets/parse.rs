//! Fuzz target: any input parses without panicking into a lossless tree with in-range errors.
#![no_main]

use gudsl_model::ast::HasName;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let parsed = gudsl_model::parse(&text);
    assert_eq!(parsed.syntax_node().to_string(), text);
    for error in parsed.errors() {
        assert!(u32::from(error.range.end()) as usize <= text.len());
    }
    // The typed layer must also hold up on whatever tree came out.
    for diagram in parsed.source_file().diagrams() {
        let _ = diagram.name().map(|n| n.text());
    }
});
