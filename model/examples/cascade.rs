//! Error-cascade survey: deletes each token of a document in turn and prints how many syntax
//! errors each single fault produces (ideally one). `cargo run --example cascade -- FILE`.
fn main() {
    let path = std::env::args().nth(1).expect("usage: cascade FILE");
    let text = std::fs::read_to_string(path).expect("readable file");
    let lexed = gudsl_model::syntax::lexer::lex(&text);
    let mut histogram = std::collections::BTreeMap::<usize, usize>::new();
    let mut worst = (0, String::new());
    let mut offset = 0usize;
    for token in &lexed.tokens {
        let len = token.len as usize;
        if !token.kind.is_trivia() {
            let mutated = format!("{}{}", &text[..offset], &text[offset + len..]);
            let n = gudsl_model::parse(&mutated).errors().len();
            *histogram.entry(n).or_default() += 1;
            if n > worst.0 {
                worst = (n, format!("deleting {:?} at {offset}", &text[offset..offset + len]));
            }
        }
        offset += len;
    }
    println!("errors per deleted token: {histogram:?}");
    println!("worst: {} errors after {}", worst.0, worst.1);
}
