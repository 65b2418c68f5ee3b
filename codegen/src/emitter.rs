//! The state of generating one kernel: the model, the types of the body being written, how each
//! name of the diagram is reached in WGSL, the text written so far and the errors found.

use std::collections::{HashMap, HashSet};

use gudsl_model::{
    ast::{self, AstNode},
    db::SourceFile,
    hir::{BodyTypes, Definition, Semantics, Ty},
    syntax::{SyntaxNode, TextRange},
};

use crate::{Binding, CodegenError, KernelParam};

/// One method or diagram generated as a function (`functions.rs`).
#[derive(Clone)]
pub(crate) struct Function<'db> {
    pub body: Body<'db>,
    /// Its name in the module: `Class_method`, or the diagram's name; a specialisation's ends in
    /// the buffers it is bound to (`Class_method_data`).
    pub name: String,
    /// The value parameters: the WGSL function's own.
    pub params: Vec<(String, Ty)>,
    /// Whether each declared parameter is a value parameter (passed), in declaration order; the
    /// others are `bound`.
    pub passed: Vec<bool>,
    /// The `out` parameters among `params`: pointers to the caller's variable
    /// (`ptr<function, T>`), read and written through.
    pub out_params: Vec<String>,
    /// The buffer, image and `shared` parameters, each bound to the kernel parameter the calls
    /// of this specialisation pass (WGSL functions take no pointers to storage or work-group
    /// memory): (the parameter's name, the kernel parameter's).
    pub bound: Vec<(String, String)>,
    pub returns: Ty,
}

/// What a function is generated from.
#[derive(Clone, PartialEq)]
pub(crate) enum Body<'db> {
    /// A method with a body, of this class.
    Method(&'db Definition, ast::Method),
    /// An activity diagram that `call behavior` reaches.
    Diagram(&'db Definition, ast::ActivityDiagram),
}

impl Body<'_> {
    /// The definition whose file holds the body.
    pub fn definition(&self) -> &Definition {
        match self {
            Body::Method(class, _) | Body::Diagram(class, _) => class,
        }
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Body::Method(_, method) => method.syntax(),
            Body::Diagram(_, diagram) => diagram.syntax(),
        }
    }

    /// Its declared parameters.
    pub fn params(&self) -> Box<dyn Iterator<Item = ast::Param>> {
        match self {
            Body::Method(_, method) => Box::new(method.params()),
            Body::Diagram(_, diagram) => Box::new(diagram.params()),
        }
    }
}

/// A call of a generated function: by whom (`None`: the kernel), of which, and where.
pub(crate) struct Call {
    pub caller: Option<usize>,
    pub callee: usize,
    pub place: (SourceFile, TextRange),
}

/// Names the generated module declares itself, besides those starting with [`GENERATED`]: the
/// uniform block, the entry point, and naga's address space of textures.
const OWN_NAMES: &[&str] = &["params", "main", "handle"];

/// Whether a GU-DSL name cannot stand in WGSL as it is: a keyword or reserved word, a
/// predeclared type, enumerant or built-in function (naga's lists, kept with the WGSL
/// specification), or a name of the generator's own.
fn is_taken(name: &str) -> bool {
    naga::keywords::wgsl::RESERVED.contains(&name)
        || naga::keywords::wgsl::BUILTIN_IDENTIFIERS.contains(&name)
        || OWN_NAMES.contains(&name)
}

/// Names the generator itself declares start with this; a user name that does is renamed.
pub(crate) const GENERATED: &str = "gudsl_";

/// The flag a `return` inside a node's loop or `switch` sets to leave the node.
pub(crate) const LEAVE_NODE: &str = "gudsl_leave_node";

/// Where a `return` in a node's statements goes: out of `depth` loops and `switch`es of the
/// node, then out of the loop around its statements; `nested_returns` counts those written
/// inside a loop or `switch` so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NodeExit {
    pub depth: usize,
    pub nested_returns: usize,
}

/// `code` without the parentheses around the whole of it (where it stands alone: a statement's
/// value, an argument, a condition).
pub(crate) fn bare(code: String) -> String {
    let enclosed = code.starts_with('(') && {
        let mut depth = 0;
        code.char_indices().all(|(at, c)| {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ => {}
            }
            depth > 0 || at == code.len() - 1
        })
    };
    if enclosed {
        code[1..code.len() - 1].to_string()
    } else {
        code
    }
}

/// A GU-DSL name as a WGSL identifier.
pub(crate) fn ident(name: &str) -> String {
    if is_taken(name) || name.starts_with(GENERATED) || name.starts_with("__") {
        format!("{name}_")
    } else {
        name.to_string()
    }
}

pub(crate) struct Emitter<'db> {
    pub sema: Semantics<'db>,
    pub file: SourceFile,
    /// The types of the body being written.
    pub types: BodyTypes,
    /// The diagram's parameters by name.
    pub params: HashMap<String, KernelParam>,
    pub errors: Vec<CodegenError>,
    pub uses_barriers: bool,
    /// The buffer and `shared` parameters an atomic function works on (`atomics.rs`).
    pub atomics: HashSet<String>,
    /// The buffers `atomic_cmpxchg` works on and their element types: each gets a helper.
    pub compare_exchanged: std::collections::BTreeSet<(String, String)>,
    /// The image parameters read through a sampler, and whether at float coordinates: each
    /// gets a texel helper, and those read at float coordinates a sampling helper too
    /// (`images.rs`).
    pub sampled_images: std::collections::BTreeMap<String, bool>,
    /// The kernel's buffers that a function bound to them writes (the kernel binds them
    /// writable).
    pub written_memory: HashSet<String>,
    /// The OpenCL class that owns the diagram: its methods are what a call that is no built-in
    /// reaches.
    pub owner: Option<&'db Definition>,
    /// The owner's methods called so far, generated as functions (`functions.rs`).
    pub functions: Vec<Function<'db>>,
    pub calls: Vec<Call>,
    /// While a function's body is written: its index among `functions` and its return type.
    pub current_function: Option<(usize, Ty)>,
    /// While the statements of a node that `return`s are written (`flow.rs`): where `return`
    /// leaves to.
    pub node_exit: Option<NodeExit>,
    out: String,
    indent: usize,
}

impl<'db> Emitter<'db> {
    pub fn new(sema: Semantics<'db>, file: SourceFile, params: HashMap<String, KernelParam>) -> Emitter<'db> {
        Emitter {
            sema,
            file,
            types: BodyTypes::default(),
            params,
            errors: Vec::new(),
            uses_barriers: false,
            atomics: HashSet::new(),
            compare_exchanged: Default::default(),
            sampled_images: Default::default(),
            written_memory: HashSet::new(),
            owner: None,
            functions: Vec::new(),
            calls: Vec::new(),
            current_function: None,
            node_exit: None,
            out: String::new(),
            indent: 0,
        }
    }

    /// Writes one line at the current indentation.
    pub fn line(&mut self, text: impl AsRef<str>) {
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(text.as_ref());
        self.out.push('\n');
    }

    /// Writes one line at the current indentation where the output stood at `at` (a
    /// [`Emitter::checkpoint`] taken at this indentation).
    pub fn insert_line(&mut self, at: usize, text: impl AsRef<str>) {
        let line = format!("{}{}\n", "    ".repeat(self.indent), text.as_ref());
        self.out.insert_str(at, &line);
    }

    /// Moves the indentation `levels` levels in (or out, when negative).
    pub fn shift(&mut self, levels: isize) {
        self.indent = self.indent.saturating_add_signed(levels);
    }

    /// Writes `open`, the lines `body` writes one level deeper, then `}`.
    pub fn block(&mut self, open: impl AsRef<str>, body: impl FnOnce(&mut Self)) {
        self.line(open);
        self.indent += 1;
        body(self);
        self.indent -= 1;
        self.line("}");
    }

    /// Writes a loop or `switch` (`open`, what `body` writes, `}`). In a node that `return`s, a
    /// `return` inside it sets `gudsl_leave_node` and breaks, and the flag breaks on after it.
    pub fn breakable(&mut self, open: impl AsRef<str>, body: impl FnOnce(&mut Self)) {
        let Some(outer) = self.node_exit else { return self.block(open, body) };
        self.node_exit = Some(NodeExit { depth: outer.depth + 1, ..outer });
        self.block(open, body);
        let inner = self.node_exit.unwrap_or(outer);
        self.node_exit = Some(NodeExit { depth: outer.depth, nested_returns: inner.nested_returns });
        if inner.nested_returns > outer.nested_returns {
            self.line(format!("if {LEAVE_NODE} {{ break; }}"));
        }
    }

    /// `return` in a node's statements: leaves the node, whose transitions follow (as on the
    /// host, `docs/host.md`); a node's statements run in a `loop` that `break` leaves.
    pub fn leave_node(&mut self, exit: NodeExit) {
        if exit.depth == 0 {
            self.line("break;");
        } else {
            self.node_exit = Some(NodeExit { nested_returns: exit.nested_returns + 1, ..exit });
            self.line(format!("{LEAVE_NODE} = true; break;"));
        }
    }

    /// Where the output and the errors stand, to [`Emitter::restore`] an attempt that failed.
    pub fn checkpoint(&self) -> (usize, usize) {
        (self.out.len(), self.errors.len())
    }

    pub fn restore(&mut self, (out, errors): (usize, usize)) {
        self.out.truncate(out);
        self.errors.truncate(errors);
    }

    pub fn take_output(&mut self) -> String {
        std::mem::take(&mut self.out)
    }

    /// Whether the last line written, at the current indentation, is a `return` (nothing after
    /// it runs).
    pub fn ends_in_return(&self) -> bool {
        let last = self.out.trim_end_matches('\n').rsplit('\n').next().unwrap_or_default();
        last.strip_prefix(&"    ".repeat(self.indent)).is_some_and(|line| line.starts_with("return"))
    }

    /// Records that `node` cannot be generated; the placeholder keeps the output well formed
    /// (it is never used: a kernel with errors is not handed out).
    pub fn unsupported(&mut self, node: &SyntaxNode, message: impl Into<String>) -> String {
        self.errors.push(CodegenError { file: self.file, range: node.text_range(), message: message.into() });
        "0".into()
    }

    /// The type of an expression of the current body.
    pub fn ty(&self, expr: &ast::Expr) -> Ty {
        self.types.of(expr).clone()
    }

    /// How a parameter is bound, if `name` is one.
    pub fn binding(&self, name: &str) -> Option<&Binding> {
        self.params.get(name).map(|p| &p.binding)
    }

    /// The WGSL that reads the name `name` (a parameter, variable or local).
    pub fn name(&self, name: &str) -> String {
        match self.binding(name) {
            Some(Binding::Uniform { .. }) => match self.params.get(name).map(|p| p.ty.dereferenced()) {
                Some(Ty::Bool) => format!("(params.{} != 0u)", ident(name)),
                _ => format!("params.{}", ident(name)),
            },
            _ if self.is_out_param(name) => format!("*{}", ident(name)),
            _ => ident(&self.global_name(name)),
        }
    }

    /// Whether `name` is an `out` parameter of the function being written.
    pub fn is_out_param(&self, name: &str) -> bool {
        self.function_written().is_some_and(|f| f.out_params.iter().any(|p| p == name))
    }

    /// The function whose body is being written; `None` in the kernel's.
    pub fn function_written(&self) -> Option<&Function<'db>> {
        self.current_function.as_ref().and_then(|(index, _)| self.functions.get(*index))
    }

    /// The kernel parameter a buffer, image or `shared` parameter stands for: itself in the
    /// kernel, the one a function's specialisation is bound to in a function.
    pub fn global_name(&self, name: &str) -> String {
        self.params.get(name).map_or_else(|| name.to_string(), |p| p.name.clone())
    }

    /// Whether `expr` names an image parameter, and which.
    pub fn image_param(&self, expr: &ast::Expr) -> Option<(String, crate::ImageType)> {
        let ast::Expr::NameExpr(name) = expr else { return None };
        let name = name.name_ref()?.text();
        match self.binding(&name) {
            Some(Binding::Image { image, .. }) => Some((name, *image)),
            _ => None,
        }
    }
}
