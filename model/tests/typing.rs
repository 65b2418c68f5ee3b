//! The expression checker as a property: random well-typed expressions, generated from the
//! grammar's operators over typed locals, check clean; one mutation of such a body — a name
//! that is not declared, a value given to a variable of a type it does not fit, a vector
//! component of the wrong kind, two arguments of a call swapped — is reported by its rule, at
//! the mutated place.

use gudsl_model::AnalysisHost;
use proptest::prelude::*;

/// A small deterministic generator driven by proptest's seed.
struct Gen(u64);

impl Gen {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Kind {
    Int,
    Float,
    Bool,
    Vector,
}

const KINDS: [Kind; 4] = [Kind::Int, Kind::Float, Kind::Bool, Kind::Vector];

/// An expression of `kind`, at most `depth` operators deep, over the locals `i`, `f`, `b`,
/// `v` and `a` (an `int[]`) of the body below.
fn expr(g: &mut Gen, kind: Kind, depth: u32) -> String {
    let leaf = depth == 0 || g.below(3) == 0;
    match kind {
        Kind::Int if leaf => ["i", "3", "a[0]", "(i % 5)"][g.below(4) as usize].to_string(),
        Kind::Int => {
            let op = ["+", "-", "*", "/"][g.below(4) as usize];
            match g.below(3) {
                0 => format!("a[{}]", expr(g, Kind::Int, depth - 1)),
                _ => format!("({} {op} {})", expr(g, Kind::Int, depth - 1), expr(g, Kind::Int, depth - 1)),
            }
        }
        Kind::Float if leaf => ["f", "1.5f", "v._x", "(float)i"][g.below(4) as usize].to_string(),
        Kind::Float => {
            let op = ["+", "-", "*", "/"][g.below(4) as usize];
            let other = if g.below(2) == 0 { Kind::Int } else { Kind::Float };
            format!("({} {op} {})", expr(g, Kind::Float, depth - 1), expr(g, other, depth - 1))
        }
        Kind::Bool if leaf => ["b", "true", "(i > 0)"][g.below(3) as usize].to_string(),
        Kind::Bool => match g.below(3) {
            0 => format!("!{}", expr(g, Kind::Bool, depth - 1)),
            1 => {
                let op = ["&&", "||"][g.below(2) as usize];
                format!("({} {op} {})", expr(g, Kind::Bool, depth - 1), expr(g, Kind::Bool, depth - 1))
            }
            _ => {
                let op = ["<", "<=", ">", ">=", "==", "!="][g.below(6) as usize];
                let side = if g.below(2) == 0 { Kind::Int } else { Kind::Float };
                format!("({} {op} {})", expr(g, side, depth - 1), expr(g, side, depth - 1))
            }
        },
        Kind::Vector if leaf => "v".to_string(),
        Kind::Vector => match g.below(3) {
            0 => format!("({} + {})", expr(g, Kind::Vector, depth - 1), expr(g, Kind::Vector, depth - 1)),
            1 => format!("({} * {})", expr(g, Kind::Vector, depth - 1), expr(g, Kind::Float, depth - 1)),
            _ => {
                let parts: Vec<String> = (0..4).map(|_| expr(g, Kind::Float, depth - 1)).collect();
                format!("new float4({})", parts.join(", "))
            }
        },
    }
}

fn type_name(kind: Kind) -> &'static str {
    match kind {
        Kind::Int => "int",
        Kind::Float => "float",
        Kind::Bool => "bool",
        Kind::Vector => "float4",
    }
}

/// An action whose body declares `r` of `ty` as `value`.
fn model(ty: &str, value: &str) -> String {
    format!(
        "ActivityDiagram Typed(int i, float f, bool b, float4 v, int[] a)\n{{\n    start s {{ => work; }}\n    action work\n    {{\n        var {ty} r = {value};\n        => done;\n    }}\n    final done;\n}}\n"
    )
}

/// An action whose body calls the owner's `mix(float4 colour, bool on, int n)` with `args`.
fn call_model(args: &[String]) -> String {
    format!(
        "ClassDiagram Owner\n{{\n    public class Mixer\n    {{\n        public float mix(float4 colour, bool on, int n) {{ return 0.0f; }}\n    }}\n}}\n\nActivityDiagram Typed(int i, float f, bool b, float4 v, int[] a), owner Owner.Mixer\n{{\n    start s {{ => work; }}\n    action work\n    {{\n        var float r = mix({});\n        => done;\n    }}\n    final done;\n}}\n",
        args.join(", ")
    )
}

/// The diagnostics of a model: (code, start offset, message).
fn diagnostics(text: &str) -> Vec<(String, usize, String)> {
    let (host, files) = AnalysisHost::with_files([("typed.gudsl".to_string(), text.to_string())]);
    let analysis = host.analysis();
    let (diagnostics, _) = analysis.diagnostics(files[0]).unwrap();
    diagnostics.iter().map(|d| (d.code.as_str().to_string(), usize::from(d.range.start()), d.message.clone())).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn well_typed_expressions_check_clean(seed in any::<u64>(), kind in 0usize..4, depth in 1u32..5) {
        let kind = KINDS[kind];
        let value = expr(&mut Gen(seed), kind, depth);
        let text = model(type_name(kind), &value);
        let found = diagnostics(&text);
        prop_assert!(found.is_empty(), "{value}: {found:?}");
    }

    #[test]
    fn an_undeclared_name_is_reported_where_it_is(seed in any::<u64>(), kind in 0usize..4, depth in 1u32..5) {
        let kind = KINDS[kind];
        let value = expr(&mut Gen(seed), kind, depth);
        // The first use of a local, renamed to a name nothing declares.
        let text = model(type_name(kind), &value);
        let body = text.find(&format!("r = {value}")).unwrap() + "r = ".len();
        let Some((at, local)) = ["i", "f", "b", "v", "a"].iter().filter_map(|l| {
            value.match_indices(l).find(|(p, _)| {
                let bytes = value.as_bytes();
                let before = *p == 0 || !(bytes[p - 1] as char).is_alphanumeric() && bytes[p - 1] != b'_' && bytes[p - 1] != b'.';
                let after = bytes.get(p + 1).is_none_or(|c| !(*c as char).is_alphanumeric() && *c != b'_');
                before && after
            }).map(|(p, l)| (p, l.to_string()))
        }).min() else { return Ok(()) };
        let mutated = format!("{}undeclared{}", &text[..body + at], &text[body + at + local.len()..]);
        let found = diagnostics(&mutated);
        prop_assert!(
            found.iter().any(|(code, start, _)| code == "E0228" && *start == body + at),
            "{value} with `{local}` undeclared: {found:?}"
        );
        prop_assert!(found.iter().all(|(code, _, _)| code == "E0228"), "{found:?}");
    }

    #[test]
    fn a_value_of_another_type_is_reported_at_the_value(seed in any::<u64>(), depth in 1u32..5) {
        // A vector given to an `int`: no conversion exists.
        let value = expr(&mut Gen(seed), Kind::Vector, depth);
        let text = model("int", &value);
        let at = text.find(&format!("r = {value}")).unwrap() + "r = ".len();
        let found = diagnostics(&text);
        prop_assert_eq!(found.len(), 1, "{}: {:?}", value, found);
        prop_assert!(found[0].0 == "E0225" && found[0].1 == at, "{value}: {found:?}");
    }

    #[test]
    fn a_vector_component_of_another_kind_is_reported_at_it(seed in any::<u64>(), depth in 1u32..4, slot in 0usize..4) {
        let mut g = Gen(seed);
        let mut parts: Vec<String> = (0..4).map(|_| expr(&mut g, Kind::Float, depth)).collect();
        parts[slot] = "\"text\"".to_string();
        let value = format!("new float4({})", parts.join(", "));
        let text = model("float4", &value);
        let at = text.find("\"text\"").unwrap();
        let found = diagnostics(&text);
        prop_assert_eq!(found.len(), 1, "{}: {:?}", value, found);
        prop_assert!(found[0].0 == "E0227" && found[0].1 == at, "{value}: {found:?}");
    }

    #[test]
    fn swapped_call_arguments_are_reported_at_them(seed in any::<u64>(), depth in 1u32..4, other in 1usize..3) {
        let mut g = Gen(seed);
        let args: Vec<String> = [Kind::Vector, Kind::Bool, Kind::Int].iter().map(|&k| expr(&mut g, k, depth)).collect();
        prop_assert!(diagnostics(&call_model(&args)).is_empty(), "{args:?}");
        // The vector swapped with the `bool` or the `int`: no conversion takes a vector there.
        let mut swapped = args.clone();
        swapped.swap(0, other);
        let text = call_model(&swapped);
        let call = text.find("= mix(").unwrap() + "= mix(".len();
        let places: Vec<usize> = [0, other]
            .iter()
            .map(|&k| call + swapped[..k].iter().map(|a| a.len() + ", ".len()).sum::<usize>())
            .collect();
        let found = diagnostics(&text);
        prop_assert!(!found.is_empty() && found.iter().all(|(code, start, _)| code == "E0227" && places.contains(start)), "{swapped:?}: {found:?}");
    }
}
