//! `call behavior` between host diagrams: `Main` calls diagrams that return values from their
//! final nodes, take `out` parameters, call each other and themselves (each call with its own
//! variables), and the report names their nodes after them. What cannot be called — a device
//! diagram, a diagram that stops without reaching a final node, a recursion without end — is an
//! error at the call, and the run stops there without crashing.

mod support;

use gudsl_host::run::{Ending, Report, RunErrorKind};
use gudsl_runtime::Gpu;
use support::{collatz_steps, prepared, samples, CLAMP_AND_COLLATZ};

/// Diagrams `Main` calls besides `CLAMP_AND_COLLATZ` (a value from one of several final nodes,
/// a loop over nodes with its own variables, a call of a call — the diagrams the device tests
/// call too): `out` parameters, recursion.
const CALLED: &str = "ActivityDiagram DivMod(int a, int b, out int quotient, out int remainder)
{
    swimlane L
    {
        start S { => divide; }
        action divide
        {
            quotient = a / b;
            remainder = a % b;
            => f;
        }
        final f;
    }
}

ActivityDiagram Factorial(int n)
{
    var int below = 1;
    swimlane L
    {
        start S
        {
            [n > 1] => recurse;
            [] => f;
        }
        action recurse
        {
            below = call behavior Factorial(n - 1);
            => f;
        }
        final f return n * below;
    }
}
";

/// Runs `Main()` of `body` (declarations and swimlanes) beside `CALLED`.
fn run(gpu: &Gpu, body: &str) -> (Report, String) {
    let text = format!("{CALLED}\nActivityDiagram Main()\n{{\n{body}\n}}\n");
    let mut sources = support::main_sources(|t| t);
    sources.retain(|(path, _)| !path.ends_with("main_full.gudsl"));
    sources.push((samples().join("host_calls_shared.gudsl").display().to_string(), CLAMP_AND_COLLATZ.into()));
    sources.push((samples().join("host_calls_test.gudsl").display().to_string(), text.clone()));
    let main = prepared(&sources, "Main").unwrap_or_else(|e| panic!("{e:?}\n{text}"));
    let dir = std::env::temp_dir().join(format!("gudsl-host-calls-{}", std::process::id()));
    (main.run(gpu, &mut support::output(&dir), &mut ()), text)
}

/// `Main` with `statements` in its one action node.
fn main_body(statements: &str) -> String {
    format!(
        "    var int q = 0;\n    var int r = 0;\n    swimlane L\n    {{\n        start S {{ => work; }}\n        \
         action work\n        {{\n            {statements}\n            => f;\n        }}\n        final f;\n    }}"
    )
}

#[test]
fn called_diagrams_return_values_and_out_parameters() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let statements = "for(var int i = 1 : 1 : i < 8) \
        { CPPMethods::printf(\"%d %d\\n\", call behavior CollatzSteps(i * 9), call behavior Clamp(i * 3, 5, 12)); }
            call behavior DivMod(-17, 5, q, r);
            CPPMethods::printf(\"%d %d\\n\", q, r);
            CPPMethods::printf(\"%d %d\\n\", call behavior Factorial(10), call behavior ClampedSteps(27));";
    let (report, text) = run(&gpu, &main_body(statements));
    assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "{text}");
    let mut wanted: Vec<String> =
        (1..8).map(|i| format!("{} {}\n", collatz_steps(i * 9), (i * 3).clamp(5, 12))).collect();
    // C's division truncates towards zero, as Rust's does.
    wanted.push(format!("{} {}\n", -17 / 5, -17 % 5));
    wanted.push(format!("{} {}\n", (1..=10).product::<i32>(), collatz_steps(27).clamp(0, 100)));
    assert_eq!(report.printed, wanted);
    let variables: Vec<(String, String)> =
        report.variables.iter().map(|(name, value)| (name.clone(), format!("{value:?}"))).collect();
    assert_eq!(variables, [("q".to_string(), "-3".to_string()), ("r".to_string(), "-2".to_string())]);
    // The called diagrams' nodes are reported under their diagram's name, each call counted.
    let runs = |name: &str| report.nodes.iter().find(|node| node.name == name).map(|node| node.runs);
    assert_eq!(runs("work"), Some(1));
    assert_eq!(runs("Factorial.recurse"), Some(9));
    assert_eq!(runs("Factorial.f"), Some(10));
    assert_eq!(runs("DivMod.divide"), Some(1));
    assert_eq!(runs("Clamp.test"), Some(8));
}

#[test]
fn an_endless_recursion_stops_the_run_at_the_call() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let body = main_body("q = call behavior Endless(1);")
        + "\n}\nActivityDiagram Endless(int n)\n{\n    swimlane L\n    {\n        start S { => f; }\n        \
           final f return call behavior Endless(n + 1);\n    }";
    // A stack of 2 MiB (a quarter of `gudsl run`'s, an eighth of the editor's runs'): the depth
    // limit comes before the stack's.
    let outcome = std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || run(&gpu, &body).0.outcome)
        .unwrap()
        .join()
        .expect("no stack overflow");
    let error = outcome.expect_err("the depth limit");
    assert_eq!(error.kind, RunErrorKind::Failed);
    assert!(error.message.contains("calls nested 200 deep: `Endless` recurses without end?"), "{error}");
}

#[test]
fn a_called_diagram_that_stops_before_a_final_node_is_an_error_at_the_call() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let body = main_body("q = call behavior Stuck(1);")
        + "\n}\nActivityDiagram Stuck(int n)\n{\n    swimlane L\n    {\n        start S { [n > 5] => f; }\n        \
           final f return n;\n    }";
    let (report, text) = run(&gpu, &body);
    let error = report.outcome.expect_err("stuck");
    assert!(error.message.contains("`Stuck` stopped at node `Stuck.S`, where no transition can be taken"), "{error}");
    let range = error.span.expect("a place").range;
    assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], "call behavior Stuck(1)");
}

#[test]
fn a_device_diagram_is_launched_not_called() {
    let text =
        format!("{CALLED}\nActivityDiagram Main()\n{{\n{}\n}}\n", main_body("call behavior AdFilterMean(0, 0, 3);"));
    let mut sources = support::main_sources(|t| t);
    sources.retain(|(path, _)| !path.ends_with("main_full.gudsl"));
    sources.push((samples().join("host_calls_test.gudsl").display().to_string(), text.clone()));
    let errors = prepared(&sources, "Main").err().expect("refused");
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].kind, RunErrorKind::NotRunnable);
    assert!(errors[0].message.contains("is a device diagram: it runs on the GPU"), "{}", errors[0].message);
}

#[test]
fn an_error_in_a_called_diagram_is_placed_there() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (report, text) = run(&gpu, &main_body("q = call behavior Clamp(7, 0, 9) / call behavior Clamp(-4, 0, 9);"));
    let error = report.outcome.expect_err("division by zero");
    assert!(error.message.contains("division by zero"), "{error}");
    let range = error.span.expect("a place").range;
    let wanted = "call behavior Clamp(7, 0, 9) / call behavior Clamp(-4, 0, 9)";
    assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], wanted);

    let body = main_body("q = call behavior Divide(1);")
        + "\n}\nActivityDiagram Divide(int n)\n{\n    swimlane L\n    {\n        start S { => f; }\n        \
           final f return 10 / (n - 1);\n    }";
    let (report, text) = run(&gpu, &body);
    let error = report.outcome.expect_err("division by zero");
    let range = error.span.expect("a place").range;
    assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], "10 / (n - 1)");
}
