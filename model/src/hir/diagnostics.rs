//! Diagnostics: what a problem is (a stable code, a severity, a byte range and a message that
//! names the thing) and the sink rules report into. The query that gathers a file's problems is
//! `validate::file_diagnostics`.

use crate::{db::SourceFile, syntax::TextRange, SyntaxErrorCode};

/// How bad a problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Severity {
    Error,
    Warning,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

/// Stable codes: `E00xx` syntax, `E02xx` semantics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DiagnosticCode {
    Syntax(SyntaxErrorCode),
    /// A type name that names nothing.
    UnresolvedType,
    /// A swimlane or diagram owner that names nothing.
    UnresolvedOwner,
    /// An owner that is not a class.
    OwnerNotAClass,
    /// A transition to a node the diagram does not have.
    UnresolvedTransitionTarget,
    /// Two things of one name in one scope.
    DuplicateName,
    /// An activity diagram without a start node.
    MissingStartNode,
    /// More than one start node.
    DuplicateStartNode,
    /// A node no transition leads to.
    UnreachableNode,
    /// A node from which no final node can be reached.
    NoPathToFinal,
    /// A transition with the wrong number of arguments for its target.
    TransitionArity,
    /// `call behavior X` where X is no activity diagram.
    UnresolvedBehavior,
    /// An import of a name that does not exist.
    UnresolvedImport,
    /// A loopWindow whose setup, test and increment sections differ in count.
    LoopWindowMismatch,
    /// `call Class::m` where the class has no method `m`.
    UnresolvedMethod,
    /// A component (or instance) whose class is not a class (or not a component).
    InvalidComponent,
    /// A connector whose interface is not an interface of its role.
    InvalidConnectorInterface,
    /// A port, connector or port instance that does not exist.
    UnresolvedConnector,
    /// A provider method without the corresponding processor signature.
    MissingProcessorSignature,
    /// A connection that does not join a provider and a processor.
    InvalidConnection,
    /// An instance field value for a field the class does not have.
    UnknownInstanceField,
    /// A binding that no connection of the component diagram allows.
    BindingNotAllowed,
    /// An attribute usage naming no attribute, or a field it does not declare.
    InvalidAttributeUse,
    /// A `shared` parameter outside a GPU (OpenCL) class.
    SharedOutsideGpuClass,
    /// A guard or condition that is not boolean.
    NotABoolean,
    /// A value assigned to a variable or field of an incompatible type.
    TypeMismatch,
    /// A call with a number of arguments no overload takes.
    CallArity,
    /// A call argument of a type the parameter does not accept.
    ArgumentType,
    /// A name in an expression that is no variable, parameter, field or type.
    UnknownName,
    /// A field or method a type does not have.
    UnknownMember,
    /// A class extending an interface or implementing a class, an interface extending a class.
    InvalidInheritance,
    /// A type that derives from itself.
    InheritanceCycle,
    /// A generic type with the wrong number of template arguments.
    TemplateArity,
    /// An assignment to a `const` local, parameter or field.
    AssignToConst,
    /// A `return` that does not fit the method's return type.
    ReturnType,
    /// A method with a return type whose body can end without `return`.
    MissingReturn,
    /// A transition into a start node or out of a final node.
    InvalidTransition,
    /// A decision node none of whose transitions has a guard.
    UnguardedDecision,
    /// A join node with a single incoming transition.
    ForkOrJoinOfOneFlow,
    /// A `read` image written, or a `write` image read.
    ImageAccess,
    /// A port's connector interface the component's class does not implement (an anonymous
    /// interface, Sec. 11.3.2.1).
    InterfaceNotImplemented,
    /// A `break` outside a loop or `switch`, a `continue` outside a loop.
    MisplacedJump,
    /// An override whose return type is not the overridden method's (nor a subtype of it).
    OverrideReturnType,
    /// `new` of an abstract class or an interface, or an instance of one.
    AbstractInstance,
    /// An assignment to, an increment of or `ref` of a value that is no variable, element or field.
    NotAssignable,
    /// A multiplicity whose lower bound exceeds its upper one (`[5 .. 1]`).
    InvertedMultiplicity,
    /// A `private` member used outside its class, a `protected` one outside its subclasses.
    InaccessibleMember,
    /// An instance member used without an object: in a `global` method, or as `Class::m()` of
    /// a method that is not `global`.
    NoObject,
    /// Device code called from host code outside a calc node, or host code from device code.
    DeviceHostCall,
    /// An image read or written by the function of another texel kind (`read_imagef` of an
    /// integer image, `read_imagei` of a float one).
    TexelKind,
    /// A method of an `OpenCL` class that calls itself, directly or through others.
    DeviceRecursion,
    /// Nodes nested in a node that holds none, or a value returned by a nested final node.
    NotAContainer,
    /// An operator applied to operands it does not take (objects in arithmetic, vectors of
    /// different widths, a number indexed).
    OperandType,
    /// A processor connector of a filter or sink instance that no binding feeds.
    UnboundProcessor,
    /// Bindings in a cycle without a buffered port.
    PipelineCycle,
    /// A parameter (instance field) value out of its range, not a constant, or missing.
    ParameterValue,
    /// A file a pipeline reads that is missing or malformed (reported by `gudsl-host`).
    PipelineInput,
    /// Images of sizes that cannot meet, or a stage that cannot run (reported by `gudsl-host`).
    PipelineMismatch,
    /// A setting that cannot act in its pipeline, a warning (reported by `gudsl-host`).
    PipelineIneffective,
    /// Device code the GPU code generator cannot generate (reported by `gudsl-codegen`).
    NotGenerated,
    /// Host code the interpreter cannot run (reported by `gudsl-host` before a run).
    NotRunnable,
    /// Where a run stopped with an error (reported by `gudsl run`).
    RunFailed,
}

impl DiagnosticCode {
    pub fn as_str(self) -> &'static str {
        match self {
            DiagnosticCode::Syntax(code) => code.as_str(),
            DiagnosticCode::UnresolvedType => "E0201",
            DiagnosticCode::UnresolvedOwner => "E0202",
            DiagnosticCode::OwnerNotAClass => "E0203",
            DiagnosticCode::UnresolvedTransitionTarget => "E0204",
            DiagnosticCode::DuplicateName => "E0205",
            DiagnosticCode::MissingStartNode => "E0206",
            DiagnosticCode::DuplicateStartNode => "E0207",
            DiagnosticCode::UnreachableNode => "E0208",
            DiagnosticCode::NoPathToFinal => "E0209",
            DiagnosticCode::TransitionArity => "E0210",
            DiagnosticCode::UnresolvedBehavior => "E0211",
            DiagnosticCode::UnresolvedImport => "E0212",
            DiagnosticCode::LoopWindowMismatch => "E0213",
            DiagnosticCode::UnresolvedMethod => "E0214",
            DiagnosticCode::InvalidComponent => "E0215",
            DiagnosticCode::InvalidConnectorInterface => "E0216",
            DiagnosticCode::UnresolvedConnector => "E0217",
            DiagnosticCode::MissingProcessorSignature => "E0218",
            DiagnosticCode::InvalidConnection => "E0219",
            DiagnosticCode::UnknownInstanceField => "E0220",
            DiagnosticCode::BindingNotAllowed => "E0221",
            DiagnosticCode::InvalidAttributeUse => "E0222",
            DiagnosticCode::SharedOutsideGpuClass => "E0223",
            DiagnosticCode::NotABoolean => "E0224",
            DiagnosticCode::TypeMismatch => "E0225",
            DiagnosticCode::CallArity => "E0226",
            DiagnosticCode::ArgumentType => "E0227",
            DiagnosticCode::UnknownName => "E0228",
            DiagnosticCode::UnknownMember => "E0229",
            DiagnosticCode::InvalidInheritance => "E0230",
            DiagnosticCode::InheritanceCycle => "E0231",
            DiagnosticCode::TemplateArity => "E0232",
            DiagnosticCode::AssignToConst => "E0233",
            DiagnosticCode::ReturnType => "E0234",
            DiagnosticCode::MissingReturn => "E0235",
            DiagnosticCode::InvalidTransition => "E0236",
            DiagnosticCode::UnguardedDecision => "E0237",
            DiagnosticCode::ForkOrJoinOfOneFlow => "E0238",
            DiagnosticCode::ImageAccess => "E0239",
            DiagnosticCode::InterfaceNotImplemented => "E0240",
            DiagnosticCode::MisplacedJump => "E0241",
            DiagnosticCode::OverrideReturnType => "E0242",
            DiagnosticCode::AbstractInstance => "E0243",
            DiagnosticCode::OperandType => "E0244",
            DiagnosticCode::NotAssignable => "E0245",
            DiagnosticCode::InvertedMultiplicity => "E0246",
            DiagnosticCode::InaccessibleMember => "E0247",
            DiagnosticCode::NoObject => "E0248",
            DiagnosticCode::DeviceHostCall => "E0249",
            DiagnosticCode::TexelKind => "E0250",
            DiagnosticCode::DeviceRecursion => "E0251",
            DiagnosticCode::NotAContainer => "E0252",
            DiagnosticCode::UnboundProcessor => "E0401",
            DiagnosticCode::PipelineCycle => "E0402",
            DiagnosticCode::ParameterValue => "E0403",
            DiagnosticCode::PipelineInput => "E0404",
            DiagnosticCode::PipelineMismatch => "E0405",
            DiagnosticCode::PipelineIneffective => "E0406",
            DiagnosticCode::NotGenerated => "E0301",
            DiagnosticCode::NotRunnable => "E0302",
            DiagnosticCode::RunFailed => "E0303",
        }
    }

    /// What the code means, in a few words (for rule lists such as SARIF's; `docs/diagnostics.md`
    /// says more).
    pub fn summary(self) -> &'static str {
        match self {
            DiagnosticCode::Syntax(code) => code.summary(),
            DiagnosticCode::UnresolvedType => "unknown or ambiguous type",
            DiagnosticCode::UnresolvedOwner => "unknown owner class of a diagram or swimlane",
            DiagnosticCode::OwnerNotAClass => "the owner is not a class",
            DiagnosticCode::UnresolvedTransitionTarget => "a transition to a node the diagram does not have",
            DiagnosticCode::DuplicateName => "a name declared twice",
            DiagnosticCode::MissingStartNode => "an activity diagram without a start node",
            DiagnosticCode::DuplicateStartNode => "more than one start node",
            DiagnosticCode::UnreachableNode => "a node never reached from the start node",
            DiagnosticCode::NoPathToFinal => "a node from which no final node can be reached",
            DiagnosticCode::TransitionArity => "wrong number of transition arguments",
            DiagnosticCode::UnresolvedBehavior => "`call behavior` of something that is no activity diagram",
            DiagnosticCode::UnresolvedImport => "an import of a name that does not exist",
            DiagnosticCode::LoopWindowMismatch => "loopWindow sections of different lengths",
            DiagnosticCode::UnresolvedMethod => "`call Class::m` of a method the class does not have",
            DiagnosticCode::InvalidComponent => "a component or instance of something that is no component class",
            DiagnosticCode::InvalidConnectorInterface => "a connector interface its role does not have",
            DiagnosticCode::UnresolvedConnector => "an unknown port, connector or port instance",
            DiagnosticCode::MissingProcessorSignature => "a provider method without its processor signature",
            DiagnosticCode::InvalidConnection => "a connection that does not join a provider and a processor",
            DiagnosticCode::UnknownInstanceField => "a value for a field the component class does not have",
            DiagnosticCode::BindingNotAllowed => "a binding no connection of the component diagram allows",
            DiagnosticCode::InvalidAttributeUse => "an unknown attribute or attribute field",
            DiagnosticCode::SharedOutsideGpuClass => "a `shared` parameter outside an OpenCL class",
            DiagnosticCode::NotABoolean => "a guard or condition that is not boolean",
            DiagnosticCode::TypeMismatch => "a value of an incompatible type",
            DiagnosticCode::CallArity => "a call with a number of arguments no overload takes",
            DiagnosticCode::ArgumentType => "a call argument of a type the parameter does not accept",
            DiagnosticCode::UnknownName => "a name that is no variable, parameter, field or type",
            DiagnosticCode::UnknownMember => "a field or method the type does not have",
            DiagnosticCode::InvalidInheritance => "a base of the wrong kind (extends vs implements)",
            DiagnosticCode::InheritanceCycle => "a type that derives from itself",
            DiagnosticCode::TemplateArity => "the wrong number of template arguments",
            DiagnosticCode::AssignToConst => "an assignment to something `const`",
            DiagnosticCode::ReturnType => "a `return` that does not fit the return type",
            DiagnosticCode::MissingReturn => "a method body that can end without `return`",
            DiagnosticCode::InvalidTransition => "a transition into a start node or out of a final node",
            DiagnosticCode::UnguardedDecision => "a decision without a guarded transition, or with two `[]`",
            DiagnosticCode::ForkOrJoinOfOneFlow => {
                "a fork with a single outgoing or a join with a single incoming transition"
            }
            DiagnosticCode::ImageAccess => "a `read` image written or a `write` image read",
            DiagnosticCode::InterfaceNotImplemented => "a port interface the component's class does not implement",
            DiagnosticCode::MisplacedJump => "a `break` or `continue` with nothing to leave",
            DiagnosticCode::OverrideReturnType => "an override that returns another type",
            DiagnosticCode::AbstractInstance => "an instance of an abstract class or an interface",
            DiagnosticCode::OperandType => "an operator applied to operands it does not take",
            DiagnosticCode::NotAssignable => "an assignment to (or `ref` of) a value that is no variable",
            DiagnosticCode::InvertedMultiplicity => "a multiplicity whose lower bound exceeds its upper one",
            DiagnosticCode::InaccessibleMember => "a private or protected member used where it is not visible",
            DiagnosticCode::NoObject => "an instance member used without an object",
            DiagnosticCode::DeviceHostCall => "device code called from host code, or host code from device code",
            DiagnosticCode::TexelKind => "an image read or written as another texel kind",
            DiagnosticCode::DeviceRecursion => "recursion in device code",
            DiagnosticCode::NotAContainer => "nodes nested where no node container is",
            DiagnosticCode::UnboundProcessor => "a filter or sink input no binding feeds",
            DiagnosticCode::PipelineCycle => "bindings in a cycle without a buffered port",
            DiagnosticCode::ParameterValue => "a parameter out of range, not constant or missing",
            DiagnosticCode::PipelineInput => "a file a pipeline reads is missing or malformed",
            DiagnosticCode::PipelineMismatch => "images that cannot meet, or a stage that cannot run",
            DiagnosticCode::PipelineIneffective => "a pipeline setting that cannot act",
            DiagnosticCode::NotGenerated => "device code the GPU code generator cannot generate",
            DiagnosticCode::NotRunnable => "host code the interpreter cannot run",
            DiagnosticCode::RunFailed => "where a run stopped with an error",
        }
    }
}

/// One problem in one file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    pub code: DiagnosticCode,
    pub severity: Severity,
    pub range: TextRange,
    pub message: String,
    /// What the range was most likely meant to read (a close name that exists, "did you mean";
    /// the keyword the rule asks for): a quick fix writes it.
    pub suggestion: Option<String>,
    /// Other places that explain it (the first declaration of a duplicate).
    pub related: Vec<Related>,
}

/// A place a diagnostic points to besides its own range.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Related {
    pub file: SourceFile,
    pub range: TextRange,
    pub message: String,
}

/// The text of `node` as a message quotes it: on one line, and cut to 40 characters (an
/// expression can be 100 000 characters long).
pub fn excerpt(node: &crate::syntax::SyntaxNode) -> String {
    const LIMIT: usize = 40;
    let text: String = node.text().to_string().split_whitespace().collect::<Vec<_>>().join(" ");
    match text.char_indices().nth(LIMIT) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text,
    }
}

/// Where validation rules and expression typing report problems, in the order found.
#[derive(Debug, Default)]
pub struct Diagnostics(Vec<Diagnostic>);

impl Diagnostics {
    fn push(
        &mut self,
        severity: Severity,
        code: DiagnosticCode,
        range: TextRange,
        message: String,
        suggestion: Option<String>,
        related: Vec<Related>,
    ) {
        self.0.push(Diagnostic { code, severity, range, message, suggestion, related });
    }

    pub fn error(&mut self, code: DiagnosticCode, range: TextRange, message: String) {
        self.push(Severity::Error, code, range, message, None, Vec::new());
    }

    pub fn warn(&mut self, code: DiagnosticCode, range: TextRange, message: String) {
        self.push(Severity::Warning, code, range, message, None, Vec::new());
    }

    /// An error whose range was most likely meant to be `suggestion` (a close name that
    /// exists): the message says "did you mean", a quick fix writes it.
    pub fn error_with_suggestion(
        &mut self,
        code: DiagnosticCode,
        range: TextRange,
        message: String,
        suggestion: Option<&str>,
    ) {
        let message = match suggestion {
            Some(name) => format!("{message}; did you mean `{name}`?"),
            None => message,
        };
        self.push(Severity::Error, code, range, message, suggestion.map(str::to_string), Vec::new());
    }

    /// An error whose range must read `replacement` (a keyword the rule asks for; the message
    /// says so): a quick fix writes it.
    pub fn error_with_replacement(
        &mut self,
        code: DiagnosticCode,
        range: TextRange,
        message: String,
        replacement: &str,
    ) {
        self.push(Severity::Error, code, range, message, Some(replacement.to_string()), Vec::new());
    }

    /// An error with other places that explain it.
    pub fn error_with_related(
        &mut self,
        code: DiagnosticCode,
        range: TextRange,
        message: String,
        related: Vec<Related>,
    ) {
        self.push(Severity::Error, code, range, message, None, related);
    }

    /// A diagnostic made elsewhere (a query's).
    pub fn add(&mut self, diagnostic: Diagnostic) {
        self.0.push(diagnostic);
    }

    pub fn into_vec(self) -> Vec<Diagnostic> {
        self.0
    }
}

/// `1 argument`, `3 arguments`.
pub(crate) fn arguments(n: usize) -> String {
    format!("{n} argument{}", if n == 1 { "" } else { "s" })
}
