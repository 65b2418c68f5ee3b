//! Deterministic synthetic GU-DSL workspaces of any size, for benchmarks and stress tests.
//!
//! Each file holds a class diagram (classes with fields, associations and method bodies that
//! call into other files' classes), an activity diagram owned by one of its classes (swimlanes,
//! all node kinds, guarded transitions with arguments) and, every few files, a component and a
//! component-instance diagram. Names are unique per file, references cross files, and every
//! generated file parses without errors.
//!
//! [`linked_workspace`] has the shape of the Langium anchor's `dmodel` workload
//! (`research/lsp-anchors/gen_workspace.py`): many small class diagrams densely linked by
//! imports, simple, qualified and same-file references, for workspace-scale latency.

use std::fmt::Write;

/// One generated file.
#[derive(Debug, Clone)]
pub struct SynthFile {
    /// Relative path, e.g. `pkg017.gudsl`.
    pub path: String,
    pub text: String,
}

/// Generates `files` files with about `total_lines` lines in all (at least one block each).
pub fn workspace(files: usize, total_lines: usize) -> Vec<SynthFile> {
    let files = files.max(1);
    let lines_per_file = (total_lines / files).max(40);
    (0..files).map(|i| file(i, files, lines_per_file)).collect()
}

/// A small deterministic pseudo-random generator (no dependency, same output everywhere).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const TYPES: &[&str] = &["int", "float", "bool", "string", "unsigned byte", "float4", "int2", "real"];

fn file(index: usize, files: usize, target_lines: usize) -> SynthFile {
    let mut rng = Rng(index as u64 * 7919 + 17);
    let mut out = String::new();
    let pkg = format!("Pkg{index:03}");
    let other = format!("Pkg{:03}", (index + 1) % files);
    let _ = writeln!(out, "// Generated workspace file {index} of {files}.");
    let _ = writeln!(out, "ClassDiagram {pkg}\n{{");
    let _ = writeln!(out, "    import {other}.*;\n");
    let _ = writeln!(out, "    public interface provider I{pkg}Provider\n    {{\n        public void provideImage(ref Image{index} image);\n    }}\n");
    let _ = writeln!(out, "    public interface processor I{pkg}Processor\n    {{\n        public void processImage(ref Image{index} image);\n    }}\n");
    let _ = writeln!(out, "    public enum Mode{index} {{ Fast, Accurate = 2, Off }}\n");
    let _ = writeln!(
        out,
        "    public attribute GeneratorVisibility\n    {{\n        public bool visible = true;\n    }}\n"
    );
    let _ = writeln!(out, "    public class Filters\n    {{\n        public global void filterMean(int width, int height, int radius);\n    }}\n");
    // Classes until roughly 60 % of the file's lines are used; the activity diagram takes the rest.
    let class_budget = target_lines * 6 / 10;
    let mut class_index = 0;
    while out.lines().count() < class_budget || class_index < 2 {
        let name = if class_index == 0 { format!("Image{index}") } else { format!("C{index}_{class_index}") };
        let base = if class_index > 0 { format!(" extends Image{index}") } else { String::new() };
        let _ = writeln!(out, "    /// Class {class_index} of {pkg}.");
        let _ = writeln!(out, "    [GeneratorVisibility(visible = true)]");
        // Class 0 and 1 are the source and the sink of the file's component diagram.
        // They implement the interfaces of their ports.
        let kind = ["source", "sink"].get(class_index).unwrap_or(&"class");
        let interfaces = ["Provider", "Processor"].get(class_index).map(|i| format!(" implements I{pkg}{i}"));
        let interfaces = interfaces.unwrap_or_default();
        let _ = writeln!(out, "    public {kind} {name}{base}{interfaces}\n    {{");
        for f in 0..4 {
            let ty = TYPES[rng.below(TYPES.len())];
            let _ = writeln!(out, "        public {ty} field{f};");
        }
        let _ = writeln!(out, "        self aggregation [0 .. *] parts : {other}.Image{};", (index + 1) % files);
        for m in 0..2 {
            let _ = writeln!(out, "        public global int compute{m}(int a, ref float b, const int c)\n        {{");
            let _ = writeln!(out, "            var int acc = a * {} + c;", rng.below(100));
            let _ = writeln!(out, "            for(var int i = 0 : 1 : i < a) {{ acc = acc + i * (b as int); }}");
            let _ = writeln!(
                out,
                "            if(acc > {}) {{ acc = acc / 2; }} else {{ acc = acc << 1; }};",
                rng.below(1000)
            );
            let _ = writeln!(out, "            call {other}.Image{}::compute{m}(acc, b, c);", (index + 1) % files);
            let _ = writeln!(out, "            return acc;\n        }}");
        }
        let _ = writeln!(out, "    }}\n");
        class_index += 1;
    }
    let _ = writeln!(out, "}}\n");
    activity(&mut out, &mut rng, index, &pkg, target_lines);
    if index.is_multiple_of(4) {
        components(&mut out, index, &pkg);
    }
    SynthFile { path: format!("pkg{index:03}.gudsl"), text: out }
}

fn activity(out: &mut String, rng: &mut Rng, index: usize, pkg: &str, target_lines: usize) {
    let _ = writeln!(out, "ActivityDiagram Ad{index}(int width, int height, out int result)\n{{");
    let _ = writeln!(out, "    public int counter = 0;\n    public float4 accumulated;\n");
    let _ = writeln!(out, "    swimlane Lane{index}, owner {pkg}.Image{index}\n    {{");
    let _ = writeln!(out, "        start S{index} {{ => init(width, height); }}\n");
    let _ = writeln!(out, "        action init(int w, int h)\n        {{\n            counter = w * h;\n            => step0;\n        }}\n");
    let mut step = 0;
    while out.lines().count() + 12 < target_lines {
        // Transitions into a calc node pass its three work-size dimensions.
        let next = if (step + 1) % 4 == 1 {
            format!("step{}(width, height, 0)", step + 1)
        } else {
            format!("step{}", step + 1)
        };
        match step % 4 {
            0 => {
                let _ = writeln!(out, "        action step{step}()\n        {{");
                let _ = writeln!(out, "            var int local = counter % {};", rng.below(50) + 1);
                let _ = writeln!(out, "            accumulated = new float4(local, 0.5f, 1.0f, 0);");
                let _ = writeln!(out, "            [local > {}] => {next};", rng.below(10));
                let _ = writeln!(out, "            [] => {next};\n        }}\n");
            }
            1 => {
                let _ = writeln!(out, "        calc step{step}()\n        {{");
                let _ =
                    writeln!(out, "            call {pkg}.Filters::filterMean(width, height, {});", rng.below(9) + 1);
                let _ = writeln!(out, "            => {next};\n        }}\n");
            }
            2 => {
                let _ = writeln!(
                    out,
                    "        loopWindow step{step}(var int u = -2, var int v = -2; u < 2, v < 2; u = u + 1, v = v + 1)"
                );
                let _ = writeln!(
                    out,
                    "        {{\n            counter = counter + u * v;\n            => {next};\n        }}\n"
                );
            }
            _ => {
                let _ = writeln!(out, "        decision step{step}\n        {{");
                let _ = writeln!(out, "            [counter >= {}] => {next};", rng.below(500));
                let _ = writeln!(out, "            [counter < 0] => done;\n            [] => {next};\n        }}\n");
            }
        }
        step += 1;
    }
    // The last step is the node kind the previous transition expects.
    let last = if step % 4 == 1 { "calc" } else { "action" };
    let _ = writeln!(out, "        {last} step{step}() {{ result = counter; => done; }}\n");
    let _ = writeln!(out, "        final done;\n    }}\n}}\n");
}

fn components(out: &mut String, index: usize, pkg: &str) {
    let _ = writeln!(out, "ComponentDiagram Components{index}\n{{");
    let _ = writeln!(out, "    source {pkg}.Image{index}\n    {{");
    let _ = writeln!(out, "        port Out{index} ( provider Out : {pkg}.I{pkg}Provider );");
    let _ = writeln!(out, "        [Link{index} source Out{index}.Out ==> target In{index}.In]\n    }}");
    let _ = writeln!(out, "    sink {pkg}.C{index}_1\n    {{\n        async buffered port In{index} ( processor In : {pkg}.I{pkg}Processor );\n    }}\n}}\n");
    let _ = writeln!(out, "ComponentInstanceDiagram Instances{index}\n{{");
    let _ = writeln!(out, "    Source{index} instantiates {pkg}.Image{index} (field0 = 1)\n    {{");
    let _ = writeln!(out, "        OutPort : Out{index} ( provider Out = I{pkg}Provider() );");
    let _ = writeln!(out, "        [ source OutPort.Out ==> target Sink{index}.InPort.In ]\n    }}");
    let _ = writeln!(out, "    Sink{index} instantiates {pkg}.C{index}_1 ( )\n    {{\n        InPort : In{index} ( processor In = I{pkg}Processor() );\n    }}\n}}");
}

/// One file of one activity diagram of `nodes` nodes in a chain, without an owner or swimlanes
/// (a diagram's own variable is the state): the size of a diagram a checker must stay linear in.
pub fn long_activity(nodes: usize) -> SynthFile {
    let mut text = String::from("ActivityDiagram Chain\n{\n    public int total = 0;\n    start s { => n0; }\n");
    for i in 0..nodes {
        let _ = writeln!(text, "    action n{i} {{ total = total + {}; => n{}; }}", i % 7, i + 1);
    }
    let _ = writeln!(text, "    final n{nodes};\n}}");
    SynthFile { path: "long.gudsl".into(), text }
}

/// One file of small activity diagrams, about `bytes` long: the size of a file a checker must
/// stay linear in (each diagram declares a variable, starts, acts and ends).
pub fn many_diagrams(bytes: usize) -> SynthFile {
    let mut text = String::with_capacity(bytes + 128);
    let mut i = 0;
    while text.len() < bytes {
        let _ = writeln!(text, "ActivityDiagram D{i}\n{{\n    start s {{ => a; }}\n    action a {{ var int x = {}; => f; }}\n    final f;\n}}", i % 10);
        i += 1;
    }
    SynthFile { path: "many.gudsl".into(), text }
}

/// The data types every linked file imports (the anchor's `base` package).
pub const LINKED_BASE_TYPES: &[&str] = &["String", "Int", "Bool", "Date", "Decimal"];

/// Classes per file of [`linked_workspace`].
pub const LINKED_CLASSES: usize = 21;

/// `files` files shaped as the Langium anchor's workload: `base.gudsl` declares five data types;
/// every other file `fNNN.gudsl` is a class diagram `M<i>` of 21 classes (about 260 lines) that
/// imports `Base` and three other files. Each class has a doc comment, fields of base types, a
/// to-many association with a simple name resolved through an import, a qualified reference to
/// another file's class, a same-file reference to the class before it, two methods, and every
/// third class `extends` a class of another file (always one with a higher class number, so
/// inheritance has no cycles). File `f001.gudsl` is the one benchmarks edit.
pub fn linked_workspace(files: usize) -> Vec<SynthFile> {
    let files = files.max(2);
    let mut out = Vec::with_capacity(files);
    let mut base = String::from("// The data types of the linked workspace.\nClassDiagram Base\n{\n");
    for ty in LINKED_BASE_TYPES {
        let _ = writeln!(base, "    public class {ty} {{ }}");
    }
    base.push_str("}\n");
    out.push(SynthFile { path: "base.gudsl".into(), text: base });
    let mut rng = Rng(42);
    for i in 1..files {
        let others: Vec<usize> = (1..files).filter(|&j| j != i).collect();
        let others = if others.is_empty() { vec![i] } else { others };
        let mut imports: Vec<usize> = Vec::new();
        while imports.len() < 3.min(others.len()) {
            let j = others[rng.below(others.len())];
            if !imports.contains(&j) {
                imports.push(j);
            }
        }
        imports.sort_unstable();
        let mut text = format!("// Linked workspace file {i} of {files}.\nClassDiagram M{i}\n{{\n    import Base.*;\n");
        for j in &imports {
            let _ = writeln!(text, "    import M{j}.*;");
        }
        for k in 0..LINKED_CLASSES {
            let j1 = imports[rng.below(imports.len())];
            let j2 = others[rng.below(others.len())];
            let (k1, k2, k3) = (rng.below(LINKED_CLASSES), rng.below(LINKED_CLASSES), rng.below(LINKED_CLASSES));
            let base = if k % 3 == 0 {
                format!(" extends M{j2}.E{j2}_{}", k + 1 + rng.below(LINKED_CLASSES - 1 - k))
            } else {
                String::new()
            };
            let _ = writeln!(text, "\n    /** Class E{i}_{k}: generated documentation for hover. */");
            let _ = writeln!(text, "    public class E{i}_{k}{base} {{");
            let _ = writeln!(text, "        public String name;\n        public Int count;");
            let _ = writeln!(text, "        self [1] items : E{j1}_{k2} [0 .. *];");
            let _ = writeln!(text, "        public M{j2}.E{j2}_{k3} owner;");
            if k > 0 {
                let _ = writeln!(text, "        public E{i}_{} prev;", k - 1);
            } else {
                let _ = writeln!(text, "        public Bool active;");
            }
            let _ = writeln!(text, "        public Base.Date created;");
            let _ = writeln!(text, "        public Bool compute(Int x, E{j1}_{k1} y);");
            let _ = writeln!(text, "        public M{j2}.E{j2}_{k2} find{k}(String key);\n    }}");
        }
        text.push_str("}\n");
        out.push(SynthFile { path: format!("f{i:03}.gudsl"), text });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::SynthFile;

    /// Every generated file checks without a diagnostic.
    fn assert_clean(files: &[SynthFile]) {
        let db = crate::db::RootDatabase::default();
        let inputs: Vec<_> =
            files.iter().map(|f| crate::db::SourceFile::new(&db, f.path.clone(), f.text.clone())).collect();
        let workspace = crate::db::Workspace::new(&db, inputs.clone());
        for (file, &input) in files.iter().zip(&inputs) {
            let diagnostics = crate::hir::file_diagnostics(&db, workspace, input);
            assert!(diagnostics.is_empty(), "{}: {:?}", file.path, diagnostics);
        }
    }

    #[test]
    fn generated_workspace_checks_clean_and_has_the_size_asked() {
        let files = super::workspace(20, 5_000);
        assert_eq!(files.len(), 20);
        let lines: usize = files.iter().map(|f| f.text.lines().count()).sum();
        assert!((4_500..=6_000).contains(&lines), "{lines} lines");
        assert_clean(&files);
    }

    #[test]
    fn long_activity_and_many_diagrams_check_clean() {
        let long = super::long_activity(50);
        assert_eq!(long.text.matches("action n").count(), 50);
        let many = super::many_diagrams(10_000);
        assert!(many.text.len() >= 10_000);
        assert_clean(&[long, many]);
    }

    #[test]
    fn linked_workspace_checks_clean_with_the_anchors_shape() {
        let files = super::linked_workspace(20);
        assert_eq!(files.len(), 20);
        let edited = &files[1];
        assert_eq!(edited.path, "f001.gudsl");
        let lines = edited.text.lines().count();
        assert!((240..=280).contains(&lines), "{lines} lines");
        assert_eq!(edited.text.matches("public class").count(), super::LINKED_CLASSES);
        assert_clean(&files);
    }
}
