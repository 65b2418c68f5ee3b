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
    (main.run(gpu, &mut support::output(&dir), &mut ()), text)
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
    /// Whether the program is a loop compiled to machine code: what it would print goes into
    /// memory (`ilog`/`ulog`, printed after the loop), and it stores into memory allocated
    /// before the loop (`m0`…`m5`, one per element type).
    native: bool,
}

/// How a `C` value stored in an element reads back.
type ReadBack = fn(u32) -> i64;

/// The element types memory is made of, with how a stored `C` value reads back.
const ELEMENTS: [(&str, ReadBack); 6] = [
    ("unsigned byte", |bits| (bits as u8) as i64),
    ("byte", |bits| (bits as u8 as i8) as i64),
    ("short", |bits| (bits as u16 as i16) as i64),
    ("unsigned short", |bits| (bits as u16) as i64),
    ("int", |bits| (bits as i32) as i64),
    ("unsigned int", |bits| bits as i64),
];

impl State {
    fn new(native: bool) -> State {
        State {
            names: ["a", "b", "c", "u", "v"],
            values: [C::int(-7), C::int(1_000_003), C::int(i32::MIN + 5), C::uint(3), C::uint(4_000_000_000)],
            native,
        }
    }

    /// A statement that prints `text` (`%u` where `unsigned`), or logs it in a native loop.
    fn print(&self, unsigned: bool, text: &str) -> String {
        match (self.native, unsigned) {
            (false, _) => format!("CPPMethods::printf(\"{}\\n\", {text});", if unsigned { "%u" } else { "%d" }),
            (true, false) => format!("ilog[ni++] = {text};"),
            (true, true) => format!("ulog[nu++] = {text};"),
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

    /// A random statement: its text, and what it prints (if it prints; `true` for `%u`).
    fn stmt(&mut self, random: &mut Random) -> (String, Option<(bool, String)>) {
        let i = random.below(5) as usize;
        let name = self.names[i];
        let target = self.values[i];
        let store = |v: C| if target.unsigned { C::uint(v.bits) } else { C::int(v.bits as i32) };
        match random.below(6) {
            0 | 1 => {
                let (text, value) = self.expr(random, 3);
                (self.print(value.unsigned, &text), Some((value.unsigned, format!("{}\n", value.printed()))))
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
                // Postfix gives the old value, prefix the new one.
                let (text, shown) =
                    if random.below(2) == 0 { (format!("{name}{op}"), target) } else { (format!("{op}{name}"), new) };
                (self.print(target.unsigned, &text), Some((target.unsigned, format!("{}\n", shown.printed()))))
            }
            _ => {
                // A store into memory of each element type, read back.
                let (text, value) = self.expr(random, 2);
                let element = random.below(6) as usize;
                let (ty, read) = ELEMENTS[element];
                let unsigned = ty == "unsigned int";
                let printed = Some((unsigned, format!("{}\n", read(value.bits))));
                if self.native {
                    return (
                        format!("m{element}[1] = {text}; {}", self.print(unsigned, &format!("m{element}[1]"))),
                        printed,
                    );
                }
                let print = self.print(unsigned, "memory[1]");
                (format!("{{ var ref {ty} memory = new {ty}[3]; memory[1] = {text}; {print} }}"), printed)
            }
        }
    }
}

/// The variables every random program starts with.
const VARIABLES: &str = "    public int a = -7;\n    public int b = 1000003;\n    public int c = -2147483643;\n    \
                         public unsigned int u = 3u;\n    public unsigned int v = 4000000000u;";

#[test]
fn random_integer_programs_print_what_c_computes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for seed in 1..=8u64 {
        let mut random = Random(0x9e37_79b9_7f4a_7c15 ^ seed);
        let mut state = State::new(false);
        let (mut statements, mut expected) = (Vec::new(), Vec::new());
        for _ in 0..150 {
            let (text, printed) = state.stmt(&mut random);
            statements.push(format!("            {text}"));
            expected.extend(printed.map(|(_, text)| text));
        }
        let body = format!(
            "{VARIABLES}\n    swimlane L\n    {{\n        \
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

/// The same random programs as one iteration of a loop compiled to machine code: what the
/// closures print, the native code computes (values logged in memory, printed after the loop).
#[test]
fn random_integer_programs_in_native_loops_compute_what_c_computes() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for seed in 1..=8u64 {
        let mut random = Random(0x9e37_79b9_7f4a_7c15 ^ seed);
        let mut state = State::new(true);
        let (mut statements, mut signed, mut unsigned) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..150 {
            let (text, printed) = state.stmt(&mut random);
            statements.push(format!("                {text}"));
            match printed {
                Some((false, text)) => signed.push(text),
                Some((true, text)) => unsigned.push(text),
                None => {}
            }
        }
        let memory: String =
            (ELEMENTS.iter().enumerate()).map(|(i, (ty, _))| format!("    public ref {ty} m{i};\n")).collect();
        let allocate: String =
            (ELEMENTS.iter().enumerate()).map(|(i, (ty, _))| format!("m{i} = new {ty}[3]; ")).collect();
        let body = format!(
            "{VARIABLES}\n{memory}    public ref int ilog;\n    public ref unsigned int ulog;\n    \
             public int ni = 0;\n    public int nu = 0;\n    public int k;\n    swimlane L\n    {{\n        \
             start S {{ => allocate; }}\n        \
             action allocate {{ {allocate}ilog = new int[200]; ulog = new unsigned int[200]; => work; }}\n        \
             action work\n        {{\n            for(var int once = 0 : 1 : once < 1)\n            {{\n{}\n            }}\n            \
             => show;\n        }}\n        \
             action show\n        {{\n            \
             for(k = 0 : 1 : k < ni) {{ CPPMethods::printf(\"%d\\n\", ilog[k]); }}\n            \
             for(k = 0 : 1 : k < nu) {{ CPPMethods::printf(\"%u\\n\", ulog[k]); }}\n            => f;\n        }}\n        \
             final f;\n    }}",
            statements.join("\n")
        );
        let (report, text) = run(&gpu, &body);
        assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "seed {seed}:\n{text}");
        assert_eq!(report.native_loops, 1, "seed {seed}: the loop ran as machine code:\n{text}");
        let expected: Vec<String> = signed.into_iter().chain(unsigned).collect();
        for (i, (got, want)) in report.printed.iter().zip(&expected).enumerate() {
            assert_eq!(got, want, "seed {seed}, value {i}:\n{text}");
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

/// The same errors inside a loop that runs as machine code: the same messages, at the same
/// expressions; the variables the loop wrote until then are kept.
#[test]
fn errors_in_a_native_loop_stop_the_run_where_they_are() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (statement, wanted, message) in [
        ("var int q = 10 / (n - n);", "10 / (n - n)", "division by zero"),
        ("var unsigned int q = 10u % ((unsigned int)n - 3u);", "10u % ((unsigned int)n - 3u)", "division by zero"),
        ("s[n] = 1;", "s[n]", "element 3 is outside"),
        ("var float x = fs[n - 2] + fs[n];", "fs[n]", "element 3 is outside"),
        ("var int k = 0; k /= n - 3;", "k /= n - 3", "division by zero"),
        ("s[n - 4] = 1;", "s[n - 4]", "element -1 is outside"),
        // `h` points at `s[1]`: h[-1] is s[0], h[-2] is outside, h[1] is s[2], h[2] outside.
        ("h[n - 4] = h[n - 2]; h[n - 5] = 1;", "h[n - 5]", "element -2 is outside"),
        ("h[n - 2] = 1; h[n - 1] = 1;", "h[n - 1]", "element 2 is outside"),
    ] {
        let body = format!(
            "    public int n = 3;\n    public int t;\n    public ref short s;\n    public ref short h;\n    \
             public ref float fs;\n    swimlane L\n    \
             {{\n        start S {{ => allocate; }}\n        \
             action allocate {{ s = new short[3]; h = s + 1; fs = new float[2]; => work; }}\n        \
             action work\n        {{\n            for(t = 0 : 1 : t < 2) {{ {statement} }}\n            => f;\n        }}\n        \
             final f;\n    }}"
        );
        let (report, text) = run(&gpu, &body);
        assert_eq!(report.native_loops, 1, "{statement}: the loop ran as machine code");
        let error = report.outcome.expect_err(statement);
        assert_eq!(error.kind, RunErrorKind::Failed, "{statement}");
        assert!(error.message.contains(message), "{statement}: {error}");
        let range = error.span.expect("a place").range;
        assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], wanted, "{statement}");
        let t = report.variables.iter().find(|(name, _)| name == "t").map(|(_, v)| format!("{v:?}"));
        assert_eq!(t.as_deref(), Some("0"), "{statement}: stopped in the first iteration");
    }
}

/// Stops the run at the `n`th question whether to.
struct StopAfter(u32);

impl gudsl_host::run::Observer for StopAfter {
    fn cancelled(&mut self) -> bool {
        self.0 = self.0.saturating_sub(1);
        self.0 == 0
    }
}

/// A loop running as machine code asks whether to stop every 65 536 iterations, as closures do.
#[test]
fn a_native_loop_stops_when_cancelled() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let text = "ActivityDiagram Test()\n{\n    public int i;\n    public int sum = 0;\n    swimlane L\n    {\n        \
                start S { => work; }\n        action work\n        {\n            \
                for(i = 0 : 1 : i < 100000000) { sum = sum + i % 7; }\n            => f;\n        }\n        \
                final f;\n    }\n}\n";
    let mut sources = support::main_sources(|t| t);
    sources.push((samples().join("interpreter_test.gudsl").display().to_string(), text.to_string()));
    let main = prepared(&sources, "Test").unwrap();
    let dir = std::env::temp_dir().join(format!("gudsl-interpreter-{}", std::process::id()));
    // Asked before S, before work, then in the loop.
    let report = main.run(&gpu, &mut support::output(&dir), &mut StopAfter(4));
    assert_eq!(report.native_loops, 1);
    let error = report.outcome.expect_err("cancelled");
    assert_eq!(error.kind, RunErrorKind::Cancelled, "{error}");
    let i = report.variables.iter().find(|(name, _)| name == "i").map(|(_, v)| format!("{v:?}")).unwrap();
    assert_eq!(i, (2 * 65_536).to_string(), "stopped after 2 × 65 536 iterations, at the second question in the loop");
}

/// Floating-point loops as machine code compute what the closures compute, bit for bit: `+`,
/// `-`, `*`, `/`, `%` (fmod), comparisons with NaN, conversions to and from `int` and `unsigned int`
/// (truncating, saturating), `float` and `double` memory, `!`, `&&`, `||`, `?:`, compound
/// assignments across kinds, `rand()`.
#[test]
fn floating_point_native_loops_compute_what_the_closures_compute() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let text = "ActivityDiagram Test()\n{\n    public ref float single;\n    public ref double wide;\n    \
                public ref int ints;\n    public int i;\n    public double x = 0.1;\n    public float y = -2.5;\n    \
                public int n = 7;\n    public unsigned int u = 4000000000u;\n    public bool flag = false;\n    \
                swimlane L\n    {\n        start S { => allocate; }\n        \
                action allocate { single = new float[64]; wide = new double[64]; ints = new int[64]; => work; }\n        \
                action work\n        {\n            for(i = 0 : 1 : i < 64)\n            {\n                \
                var double nan = (x - x) / (x - x);\n                \
                x = x * 1.7 - (double)i / 3.0 + y;\n                \
                y = y + (float)(x % 2.5) - (float)u / 1000000000.0f;\n                \
                n += (int)(x * 1000.0) + CPPMethods::rand() % 1000;\n                \
                u -= (unsigned int)(y * -3.0) + 1u;\n                \
                flag = !flag && (x < y || nan != nan) || (nan == nan);\n                \
                single[i] = (float)(x / 7.0);\n                \
                wide[i] = flag ? x * x : -(double)n;\n                \
                ints[i] = (int)(wide[i] / 1.0e3) + (nan < 1.0 ? 1 : 0) + (int)(1.0e12 * y);\n                \
                wide[i] += single[i] * 0.5f;\n            }\n            => show;\n        }\n        \
                action show\n        {\n            for(i = 0 : 1 : i < 64)\n            {\n                \
                CPPMethods::printf(\"%.17g %.9g \", wide[i], (double)single[i]);\n                \
                CPPMethods::printf(\"%d %d\\n\", ints[i], i);\n            }\n            \
                CPPMethods::printf(\"%.17g %.9g \", x, (double)y);\n            \
                CPPMethods::printf(\"%d %u\\n\", n, u);\n            => f;\n        }\n        final f;\n    }\n}\n";
    let mut sources = support::main_sources(|t| t);
    sources.push((samples().join("interpreter_test.gudsl").display().to_string(), text.to_string()));
    let dir = std::env::temp_dir().join(format!("gudsl-interpreter-{}", std::process::id()));
    let mut reports = Vec::new();
    for native in [true, false] {
        let mut main = prepared(&sources, "Test").unwrap_or_else(|e| panic!("{e:?}"));
        main.set_native_loops(native);
        let report = main.run(&gpu, &mut support::output(&dir), &mut ());
        assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "native {native}");
        reports.push(report);
    }
    assert_eq!(reports[0].native_loops, 1, "the work loop ran as machine code");
    assert_eq!(reports[1].native_loops, 0);
    assert_eq!(reports[0].printed.len(), 65 * 2);
    assert_eq!(reports[0].printed, reports[1].printed);
}

/// A loop that cannot be native (it prints) still runs the numeric loops inside it natively.
#[test]
fn numeric_loops_inside_a_printing_loop_run_natively() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let body = "    public int i;\n    public int j;\n    public int sum;\n    swimlane L\n    {\n        \
                start S { => work; }\n        action work\n        {\n            \
                for(i = 0 : 1 : i < 3)\n            {\n                sum = 0;\n                \
                for(j = 0 : 1 : j <= i * 10) { sum += j; }\n                \
                CPPMethods::printf(\"%d %d\\n\", i, sum);\n            }\n            => f;\n        }\n        \
                final f;\n    }";
    let (report, text) = run(&gpu, body);
    assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "{text}");
    assert_eq!(report.printed, ["0 0\n", "1 55\n", "2 210\n"]);
    assert_eq!(report.native_loops, 3, "the inner loop, once per outer iteration");
}
