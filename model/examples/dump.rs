//! Prints the syntax tree and errors of a GU-DSL file: `cargo run --example dump -- FILE`.
fn main() {
    let path = std::env::args().nth(1).expect("usage: dump FILE");
    let text = std::fs::read_to_string(path).expect("readable file");
    let parse = gudsl_model::parse(&text);
    print!("{}", gudsl_model::syntax::debug_dump(&parse));
}
