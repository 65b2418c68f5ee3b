//! Prints a file formatted: `cargo run --example fmt -- FILE`.
fn main() {
    let path = std::env::args().nth(1).expect("usage: fmt FILE");
    let text = std::fs::read_to_string(path).expect("readable file");
    print!("{}", gudsl_model::format::format(&gudsl_model::parse(&text)).unwrap_or(text));
}
