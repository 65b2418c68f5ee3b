//! The host interpreter computes as C does: random programs of `int` and `unsigned int`
//! arithmetic (every operator, casts, ternaries, compound assignments, increments, stores into
//! memory of each element type) print what the same operations give in Rust's wrapping
//! arithmetic; a division by zero and an index outside its memory stop the run at the
//! expression that did it.

mod support;

use gudsl_host::run::{Ending, Report, RunErrorKind};
use gudsl_runtime::Gpu;
use support::{prepared, samples};

/// Runs `Test()` of `body` (declarations and swimlanes) with the bundled framework.
fn run(gpu: &Gpu, body: &str) -> (Report, String) {
    let text = format!("ActivityDiagram Test()\n{{\n{body}\n}}\n");
    let mut sources = support::main_sources(|t| t);
    sources.push((samples().join("interpreter_test.gudsl").display().to_string(), text.clone()));
    let main = prepared(&sources, "Test").unwrap_or_else(|e| panic!("{e:?}\n{text}"));
    let dir = std::env::temp_dir().join(format!("gudsl-interpreter-{}", std::process::id()));
    (main.run(gpu, &dir, &mut ()), text)
}

/// xorshift64: the programs are the same on every run.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// A C value: `int` or `unsigned int`, as bits.
#[derive(Clone, Copy)]
struct C {
    bits: u32,
    unsigned: bool,
}

impl C {
    fn int(v: i32) -> C {
        C { bits: v as u32, unsigned: false }
    }

    fn uint(v: u32) -> C {
        C { bits: v, unsigned: true }
    }

    fn printed(self) -> String {
        if self.unsigned {
            self.bits.to_string()
        } else {
            (self.bits as i32).to_string()
        }
    }
}

const OPS: [&str; 10] = ["+", "-", "*", "/", "%", "<<", ">>", "&", "|", "^"];

/// `l op r` in C: the usual arithmetic conversions (the left operand's type for shifts),
/// wrapping, shifts by the amount modulo 32 (what the interpreter does where C leaves it
/// undefined).
fn binary(op: &str, l: C, r: C) -> C {
    let unsigned = if matches!(op, "<<" | ">>") { l.unsigned } else { l.unsigned || r.unsigned };
    let (a, b) = (l.bits, r.bits);
    let bits = if unsigned {
        match op {
            "+" => a.wrapping_add(b),
            "-" => a.wrapping_sub(b),
            "*" => a.wrapping_mul(b),
            "/" => a / b,
            "%" => a % b,
            "<<" => a.wrapping_shl(b),
            ">>" => a.wrapping_shr(b),
            "&" => a & b,
            "|" => a | b,
            _ => a ^ b,
        }
    } else {
        let (a, b) = (a as i32, b as i32);
        (match op {
            "+" => a.wrapping_add(b),
            "-" => a.wrapping_sub(b),
            "*" => a.wrapping_mul(b),
            "/" => a.wrapping_div(b),
            "%" => a.wrapping_rem(b),
            "<<" => a.wrapping_shl(b as u32),
            ">>" => a.wrapping_shr(b as u32),
            "&" => a & b,
            "|" => a | b,
            _ => a ^ b,
        }) as u32
    };
    C { bits, unsigned }
}

fn less(l: C, r: C) -> bool {
    if l.unsigned || r.unsigned {
        l.bits < r.bits
    } else {
        (l.bits as i32) < (r.bits as i32)
    }
}

/// The variables of the random programs: `int a, b, c` and `unsigned int u, v`.
struct State {
    names: [&'static str; 5],
    values: [C; 5],
}

impl State {
    fn new() -> State {
        State {
            names: ["a", "b", "c", "u", "v"],
            values: [C::int(-7), C::int(1_000_003), C::int(i32::MIN + 5), C::uint(3), C::uint(4_000_000_000)],
        }
    }

    /// A random expression of `depth` at most: its text and value.
    fn expr(&self, random: &mut Random, depth: u32) -> (String, C) {
        let choice = if depth == 0 { random.below(3) } else { random.below(9) };
        match choice {
            0 | 1 => {
                let i = random.below(5) as usize;
                (self.names[i].to_string(), self.values[i])
            }
            2 => match random.below(3) {
                0 => {
                    let v = random.below(100) as i32;
                    (v.to_string(), C::int(v))
                }
                1 => {
                    let v = random.next() as u32;
                    (format!("{v}u"), C::uint(v))
                }
                _ => {
                    let v = (random.next() as u32 >> 1) as i32;
                    (v.to_string(), C::int(v))
                }
            },
            3..=5 => {
                let op = OPS[random.below(OPS.len() as u64) as usize];
                let (lt, l) = self.expr(random, depth - 1);
                let (rt, r) = self.expr(random, depth - 1);
                if matches!(op, "/" | "%") {
                    // Never zero: `| 1`.
                    let one = if r.unsigned { "1u" } else { "1" };
                    let r = binary("|", r, C { bits: 1, unsigned: r.unsigned });
                    (format!("({lt} {op} ({rt} | {one}))"), binary(op, l, r))
                } else {
                    (format!("({lt} {op} {rt})"), binary(op, l, r))
                }
            }
            6 => {
                let (t, v) = self.expr(random, depth - 1);
                match random.below(4) {
                    0 => (format!("(-{t})"), C { bits: v.bits.wrapping_neg(), unsigned: v.unsigned }),
                    1 => (format!("(~{t})"), C { bits: !v.bits, unsigned: v.unsigned }),
                    2 => (format!("((int){t})"), C::int(v.bits as i32)),
                    _ => (format!("((unsigned int){t})"), C::uint(v.bits)),
                }
            }
            _ => {
                let (ct1, c1) = self.expr(random, depth - 1);
                let (ct2, c2) = self.expr(random, depth - 1);
                let (at, a) = self.expr(random, depth - 1);
                let (bt, b) = self.expr(random, depth - 1);
                // Both branches of the same type, as C's conversions would make them.
                let unsigned = a.unsigned || b.unsigned;
                let pick = if less(c1, c2) { a } else { b };
                let cast = if unsigned { "(unsigned int)" } else { "(int)" };
                (format!("(({ct1} < {ct2}) ? {cast}{at} : {cast}{bt})"), C { bits: pick.bits, unsigned })
            }
        }
    }

    /// A random statement: its text, and what it prints (if it prints).
    fn stmt(&mut self, random: &mut Random) -> (String, Option<String>) {
        let i = random.below(5) as usize;
        let name = self.names[i];
        let target = self.values[i];
        let store = |v: C| if target.unsigned { C::uint(v.bits) } else { C::int(v.bits as i32) };
        match random.below(6) {
            0 | 1 => {
                let (text, value) = self.expr(random, 3);
                let format = if value.unsigned { "%u" } else { "%d" };
                (format!("CPPMethods::printf(\"{format}\\n\", {text});"), Some(format!("{}\n", value.printed())))
            }
            2 => {
                let (text, value) = self.expr(random, 2);
                self.values[i] = store(value);
                (format!("{name} = {text};"), None)
            }
            3 => {
                let op = ["+", "-", "*", "&", "|", "^", "<<", ">>"][random.below(8) as usize];
                let (text, value) = self.expr(random, 2);
                self.values[i] = store(binary(op, target, value));
                (format!("{name} {op}= {text};"), None)
            }
            4 => {
                let (op, delta) = if random.below(2) == 0 { ("++", 1) } else { ("--", u32::MAX) };
                let new = store(binary("+", target, C { bits: delta, unsigned: target.unsigned }));
                self.values[i] = new;
                let format = if target.unsigned { "%u" } else { "%d" };
                // Postfix gives the old value, prefix the new one.
                if random.below(2) == 0 {
                    (
                        format!("CPPMethods::printf(\"{format}\\n\", {name}{op});"),
                        Some(format!("{}\n", target.printed())),
                    )
                } else {
                    (format!("CPPMethods::printf(\"{format}\\n\", {op}{name});"), Some(format!("{}\n", new.printed())))
                }
            }
            _ => {
                // A store into memory of each element type, read back.
                let (text, value) = self.expr(random, 2);
                let (ty, read) = [
                    ("unsigned byte", (value.bits as u8) as i64),
                    ("byte", (value.bits as u8 as i8) as i64),
                    ("short", (value.bits as u16 as i16) as i64),
                    ("unsigned short", (value.bits as u16) as i64),
                    ("int", (value.bits as i32) as i64),
                    ("unsigned int", value.bits as i64),
                ][random.below(6) as usize];
                let format = if ty == "unsigned int" { "%u" } else { "%d" };
                let text = format!(
                    "{{ var ref {ty} memory = new {ty}[3]; memory[1] = {text}; CPPMethods::printf(\"{format}\\n\", memory[1]); }}"
                );
                (text, Some(format!("{read}\n")))
            }
        }
    }
}

#[test]
fn random_integer_programs_print_what_c_computes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for seed in 1..=8u64 {
        let mut random = Random(0x9e37_79b9_7f4a_7c15 ^ seed);
        let mut state = State::new();
        let (mut statements, mut expected) = (Vec::new(), Vec::new());
        for _ in 0..150 {
            let (text, printed) = state.stmt(&mut random);
            statements.push(format!("            {text}"));
            expected.extend(printed);
        }
        let body = format!(
            "    public int a = -7;\n    public int b = 1000003;\n    public int c = -2147483643;\n    \
             public unsigned int u = 3u;\n    public unsigned int v = 4000000000u;\n    swimlane L\n    {{\n        \
             start S {{ => work; }}\n        action work\n        {{\n{}\n            => f;\n        }}\n        \
             final f;\n    }}",
            statements.join("\n")
        );
        let (report, text) = run(&gpu, &body);
        assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "seed {seed}:\n{text}");
        for (i, (got, want)) in report.printed.iter().zip(&expected).enumerate() {
            assert_eq!(got, want, "seed {seed}, print {i}:\n{text}");
        }
        assert_eq!(report.printed.len(), expected.len());
    }
}

#[test]
fn a_division_by_zero_and_an_index_outside_stop_the_run_where_they_are() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (statement, wanted, message) in [
        ("var int q = 10 / (n - n);", "10 / (n - n)", "division by zero"),
        ("var unsigned int q = 10u % ((unsigned int)n - 3u);", "10u % ((unsigned int)n - 3u)", "division by zero"),
        ("var ref short s = new short[3]; s[n] = 1;", "s[n]", "element 3 is outside"),
        ("var ref float s = new float[2]; var float x = s[n - 2] + s[n];", "s[n]", "element 3 is outside"),
        ("var int k = 0; k /= n - 3;", "k /= n - 3", "division by zero"),
    ] {
        let body = format!(
            "    public int n = 3;\n    swimlane L\n    {{\n        start S {{ => work; }}\n        action work\n        \
             {{\n            {statement}\n            => f;\n        }}\n        final f;\n    }}"
        );
        let (report, text) = run(&gpu, &body);
        let error = report.outcome.expect_err(statement);
        assert_eq!(error.kind, RunErrorKind::Failed, "{statement}");
        assert!(error.message.contains(message), "{statement}: {error}");
        let range = error.span.expect("a place").range;
        assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], wanted, "{statement}");
    }
}
