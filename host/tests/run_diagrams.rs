//! Host diagrams run: `Main` of Listings 30–33 end to end on the bundled image (its viewer
//! images against the CPU references of the listings, the findIndex result against the shuffled
//! buffer it searched), C's arithmetic and control flow in host code, and the error paths — a
//! missing image, constructs that cannot run (found before anything runs), a cancelled run.

mod support;

use std::path::{Path, PathBuf};

use gudsl_host::run::{Ending, Observer, RunErrorKind, Value};
use gudsl_runtime::{listings, Gpu};
use support::{check_mean, main_sources, prepared, samples, Rgba};

/// The samples (with `edit` applied to each text) and `extra` files, as `(path, text)`.
fn sources(edit: impl Fn(String) -> String, extra: &[(&str, &str)]) -> Vec<(String, String)> {
    let mut out = main_sources(edit);
    out.extend(extra.iter().map(|(path, text)| (samples().join(path).display().to_string(), text.to_string())));
    out
}

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gudsl-run-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn rgb(path: &Path) -> (u32, u32, Vec<u8>) {
    let image = image::open(path).unwrap().to_rgb8();
    (image.width(), image.height(), image.into_raw())
}

/// The RGB channels of packed RGBA texels.
fn drop_alpha(rgba: &[u8]) -> Vec<u8> {
    rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

fn variable<'a>(report: &'a gudsl_host::run::Report, name: &str) -> &'a Value {
    &report.variables.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no variable {name}")).1
}

#[test]
fn main_runs_end_to_end_and_its_viewer_shows_what_the_listings_compute() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let main = prepared(&sources(|t| t, &[]), "Main").unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(main.kernels().len(), 4, "bilateral, mean and the two findIndex stages");
    let dir = out_dir("main");
    let report = main.run(&gpu, &mut support::output(&dir), &mut ());
    assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "{report:?}");

    let names: Vec<String> =
        report.images.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["viewer1-image0.png", "viewer1-image1.png", "viewer1-image2.png", "viewer1-image3.png"]);
    let input = image::open(samples().join("seed/tof_amplitude.png")).unwrap().to_rgba8();
    let (width, height) = (input.width() as usize, input.height() as usize);
    let input = input.into_raw();
    let (w, h, original) = rgb(&report.images[0]);
    assert_eq!((w as usize, h as usize, &original), (width, height, &drop_alpha(&input)));
    assert_eq!(rgb(&report.images[3]).2, original, "image objects 0 and 3 keep the original");

    let (_, _, mean) = rgb(&report.images[2]);
    let rgba = Rgba { width, height, texels: input.clone() };
    check_mean(&mean, 3, &rgba, 10).unwrap_or_else(|e| panic!("Listing 15, kernel size 10: {e}"));
    if gpu.describe().contains("llvmpipe") {
        // Lavapipe divides exactly: the CPU's result, value for value.
        assert_eq!(mean, drop_alpha(&listings::mean(&input, width, height, 10)), "Listing 15, kernel size 10");
    }
    let (_, _, bilateral) = rgb(&report.images[1]);
    let cpu = drop_alpha(&listings::bilateral(&input, width, height, 5.0, 10.0, 50.0));
    let off: Vec<u8> = bilateral.iter().zip(&cpu).filter(|(a, b)| a != b).map(|(a, b)| a.abs_diff(*b)).collect();
    assert!(off.iter().all(|d| *d <= 1) && off.len() * 1000 <= cpu.len(), "bilateral: {} values off", off.len());

    // findIndex: the first index of an element >= the one at valueIndexToFind.
    let elements = variable(&report, "bufferAllElements");
    let wanted = elements.element(4711).unwrap();
    let Value::UInt(wanted) = wanted else { panic!("{wanted:?}") };
    let first = (0..1_048_576).find(|&i| matches!(elements.element(i), Some(Value::UInt(v)) if v >= wanted)).unwrap();
    let found = variable(&report, "outFindLastElement").element(0).unwrap();
    assert!(matches!(found, Value::Int(i) if i as i64 == first), "found {found:?}, the first is {first}");
    assert_eq!(report.printed, [format!("first index of a value >= {wanted}: {first}\n")]);

    let calcs: Vec<(&str, u32)> = report.calcs.iter().map(|c| (c.node.as_str(), c.launches)).collect();
    assert_eq!(
        calcs,
        [("filterBilateralCL", 1), ("filterMean", 1), ("findIndexFirstStage", 1), ("findIndexSecondStage", 1)]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A host diagram of the workspace: `Test()` whose nodes print what they compute.
fn run_host(body: &str) -> gudsl_host::run::Report {
    let gpu = Gpu::for_tests().expect("a device");
    let text = format!("ActivityDiagram Test()\n{{\n{body}\n}}\n");
    let main = prepared(&sources(|t| t, &[("host_test.gudsl", &text)]), "Test").unwrap_or_else(|e| panic!("{e:?}"));
    main.run(&gpu, &mut support::output(&out_dir("host")), &mut ())
}

#[test]
fn host_code_computes_as_c_does() {
    if Gpu::for_tests().is_none() {
        return;
    }
    let report = run_host(
        r#"
    public int a = -7;
    public unsigned int u = 3u;
    public float f;
    public ref int numbers;
    public int found;
    swimlane L
    {
        start S { => arithmetic; }
        action arithmetic
        {
            CPPMethods::printf("%d %d %d %d\n", a / 2, a % 2, a >> 1, 7 << 2);
            u = u - 4u;
            CPPMethods::printf("%u %u\n", u, u / 2u);
            f = 7 / 2;
            CPPMethods::printf("%.2f %.2f %d\n", f, 7.0f / 2, (int)-3.7f);
            => loops(5);
        }
        action loops(int n)
        {
            numbers = new int[n];
            var int i;
            for (i = 0 : 1 : i < n) { numbers[i] = i * i; }
            var ref int third = numbers + 2;
            var int sum = 0;
            do { sum += third[0]; third = third + 1; } loop (third[0] < 16);
            var int k = 0;
            loop (k < 3) { k++; if (k == 2) { continue; } sum = sum + 100; }
            switch sum: { case 213: CPPMethods::printf("case %d\n", sum); break; default: CPPMethods::printf("default\n"); }
            CPPMethods::printf("%d %d\n", sum, numbers[4]);
            var int window = 0;
            loopwindow2D(u = -1 : 1, v = -2 : 2) { window = window + 1 + u * v; }
            CPPMethods::printf("window %d\n", window);
            var int m = 0;
            numbers[m++] += 1000;
            CPPMethods::printf("%d %d %d\n", m, numbers[0], numbers[1]);
            numbers[0] -= 1000;
            => search(n, found);
        }
        action search(int n, out int index)
        {
            var int i;
            for (i = 0 : 1 : i < n)
            {
                if (numbers[i] >= 9) { index = i; return; }
            }
            => counted;
        }
        loop counted(var int j = 0; j < 3; j = j + 1)
        {
            CPPMethods::printf("%d:%d ", j, found);
            [found == 3] => f;
        }
        final f;
    }
"#,
    );
    assert_eq!(report.outcome, Ok(Ending::Final("f".into())), "{report:?}");
    assert_eq!(
        report.printed,
        [
            "-3 -1 -4 28\n",
            "4294967295 2147483647\n",
            "3.00 3.50 -3\n",
            "case 213\n",
            "213 16\n",
            "window 15\n",
            "1 1000 1\n",
            "0:3 ",
            "1:3 ",
            "2:3 "
        ]
    );
}

#[test]
fn a_missing_image_stops_the_run_at_the_load_with_the_path() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let edit = |t: String| t.replace("\"tof_amplitude.png\"", "\"no_such_image.png\"");
    let main = prepared(&sources(edit, &[]), "Main").unwrap();
    let report = main.run(&gpu, &mut support::output(&out_dir("missing")), &mut ());
    let error = report.outcome.unwrap_err();
    assert_eq!(error.kind, RunErrorKind::Failed);
    assert!(error.message.contains("no_such_image.png") && error.message.contains("cannot read"), "{error}");
    let text = std::fs::read_to_string(samples().join("seed/main_full.gudsl")).unwrap();
    let range = error.span.unwrap().range;
    assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], "image.load(asd)");
    assert!(report.images.is_empty() && report.calcs.is_empty());
}

#[test]
fn what_cannot_run_is_found_before_anything_runs() {
    let text = r#"ActivityDiagram Broken(int x)
{
    swimlane L
    {
        start S { => split; }
        fork split { => a; => b; }
        action a { call behavior Other(1); => f; }
        action b { var int y = this; => f; }
        calc c() { call Reduction.FindIndex::findMinimumIndexFirstStage(null, null, 1, 4, 1, 1u, 1); => f; }
        final f;
    }
}
ActivityDiagram Other() { swimlane L { start S { => f; } final f; } }
"#;
    let errors = match prepared(&sources(|t| t, &[("broken.gudsl", text)]), "Broken") {
        Ok(_) => panic!("Broken is not runnable"),
        Err(errors) => errors,
    };
    let found: Vec<(&str, &str)> = errors
        .iter()
        .map(|e| {
            let range = e.span.unwrap().range;
            (&text[usize::from(range.start())..usize::from(range.end())], e.message.as_str())
        })
        .collect();
    let has = |snippet: &str, words: &str| found.iter().any(|(s, m)| s.starts_with(snippet) && m.contains(words));
    assert!(errors.iter().all(|e| e.kind == RunErrorKind::NotRunnable));
    assert!(has("int x", "parameters"), "{found:#?}");
    assert!(has("fork split", "one flow"), "{found:#?}");
    assert!(has("call behavior Other(1)", "takes 0 argument(s), 1 are given"), "{found:#?}");
    assert!(has("this", "this"), "{found:#?}");
}

/// Stops the run when it reaches a node.
struct StopAt(&'static str, Vec<String>);

impl Observer for StopAt {
    fn node(&mut self, name: &str) {
        self.1.push(name.to_string());
    }
    fn cancelled(&mut self) -> bool {
        self.1.last().is_some_and(|n| n == self.0)
    }
}

#[test]
fn a_cancelled_run_stops_between_nodes_and_says_where() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let main = prepared(&sources(|t| t, &[]), "Main").unwrap();
    let mut observer = StopAt("syncToGPU", Vec::new());
    let report = main.run(&gpu, &mut support::output(&out_dir("cancel")), &mut observer);
    let error = report.outcome.unwrap_err();
    assert_eq!(error.kind, RunErrorKind::Cancelled);
    assert!(error.message.contains("processImages") || error.message.contains("addViewerImages"), "{error}");
    assert_eq!(observer.1.last().map(String::as_str), Some("syncToGPU"));
    assert!(report.calcs.is_empty(), "no kernel ran");
}
