//! The typed node wrappers and their accessors, grouped by diagram kind.

use super::{ast_enum, ast_node, child, children, token, AstNode};
use crate::syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken};

// ---------------------------------------------------------------- shared

ast_node!(
    /// The root of a document.
    SourceFile, SOURCE_FILE
);
ast_node!(
    /// A defining name.
    Name, NAME
);
ast_node!(
    /// A reference by name.
    NameRef, NAME_REF
);
ast_node!(
    /// A qualified name `A.B.C`.
    Path, PATH
);
ast_node!(Import, IMPORT);
ast_node!(AttributeList, ATTRIBUTE_LIST);
ast_node!(AttributeUse, ATTRIBUTE_USE);
ast_node!(NamedArgList, NAMED_ARG_LIST);
ast_node!(
    /// `name = value` in attribute arguments and instance field values.
    NamedArg, NAMED_ARG
);
ast_node!(
    /// Visibility, `abstract` and qualifiers.
    Modifiers, MODIFIERS
);
ast_node!(TypeRef, TYPE_REF);
ast_node!(TypeArgs, TYPE_ARGS);

impl SourceFile {
    pub fn diagrams(&self) -> impl Iterator<Item = Diagram> {
        children(&self.syntax)
    }
    pub fn imports(&self) -> impl Iterator<Item = Import> {
        children(&self.syntax)
    }
}

impl Name {
    pub fn ident(&self) -> Option<SyntaxToken> {
        token(&self.syntax, IDENT)
    }
    pub fn text(&self) -> String {
        self.ident().map(|t| t.text().to_string()).unwrap_or_default()
    }
}

impl NameRef {
    pub fn ident(&self) -> Option<SyntaxToken> {
        token(&self.syntax, IDENT)
    }
    pub fn text(&self) -> String {
        self.ident().map(|t| t.text().to_string()).unwrap_or_default()
    }
}

impl Path {
    pub fn segments(&self) -> impl Iterator<Item = NameRef> {
        children(&self.syntax)
    }
    /// The dotted text without trivia: `A.B.C`.
    pub fn text(&self) -> String {
        self.segments().map(|s| s.text()).collect::<Vec<_>>().join(".")
    }
    pub fn last_segment(&self) -> Option<NameRef> {
        self.segments().last()
    }
}

/// What an import brings in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ImportTarget {
    /// `import A.B;`
    Name(Path),
    /// `import A.B.*;`
    Wildcard(Path),
    /// `import "<QImage>";` (a C++ header; not resolved).
    Header(SyntaxToken),
}

impl Import {
    pub fn target(&self) -> Option<ImportTarget> {
        if let Some(lit) = child::<Literal>(&self.syntax) {
            return lit.token().map(ImportTarget::Header);
        }
        let path = child::<Path>(&self.syntax)?;
        Some(if token(&self.syntax, STAR).is_some() { ImportTarget::Wildcard(path) } else { ImportTarget::Name(path) })
    }
}

impl AttributeList {
    pub fn uses(&self) -> impl Iterator<Item = AttributeUse> {
        children(&self.syntax)
    }
}

impl AttributeUse {
    pub fn path(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = NamedArg> {
        child::<NamedArgList>(&self.syntax).into_iter().flat_map(|l| l.args())
    }
}

impl NamedArgList {
    pub fn args(&self) -> impl Iterator<Item = NamedArg> {
        children(&self.syntax)
    }
}

impl NamedArg {
    pub fn name(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn value(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

/// Visibility of a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Visibility {
    Public,
    Protected,
    Private,
}

impl Modifiers {
    pub fn visibility(&self) -> Option<Visibility> {
        self.keywords().find_map(|k| match k {
            PUBLIC_KW => Some(Visibility::Public),
            PROTECTED_KW => Some(Visibility::Protected),
            PRIVATE_KW => Some(Visibility::Private),
            _ => None,
        })
    }
    /// Keyword kinds in order (`PUBLIC_KW`, `CONST_KW`, `GLOBAL_KW`, …).
    pub fn keywords(&self) -> impl Iterator<Item = SyntaxKind> {
        self.syntax.children_with_tokens().filter_map(|e| e.into_token()).map(|t| t.kind()).filter(|k| k.is_keyword())
    }
    pub fn has(&self, kind: SyntaxKind) -> bool {
        self.keywords().any(|k| k == kind)
    }
}

/// Items with attribute lists and modifiers in front.
pub trait HasModifiers: AstNode {
    fn modifiers(&self) -> Option<Modifiers> {
        child(self.syntax())
    }
    fn attribute_lists(&self) -> Vec<AttributeList> {
        children(self.syntax()).collect()
    }
    fn has_modifier(&self, kind: SyntaxKind) -> bool {
        self.modifiers().is_some_and(|m| m.has(kind))
    }
}

/// Items with a defining name.
pub trait HasName: AstNode {
    fn name(&self) -> Option<Name> {
        child(self.syntax())
    }
}

impl TypeRef {
    /// The user type's qualified name (`None` for built-ins).
    pub fn path(&self) -> Option<Path> {
        child(&self.syntax)
    }
    /// The built-in type keyword (`INT_KW`, …), if a built-in.
    pub fn builtin(&self) -> Option<SyntaxToken> {
        self.syntax.children_with_tokens().filter_map(|e| e.into_token()).find(|t| t.kind().is_builtin_type())
    }
    pub fn is_ref(&self) -> bool {
        token(&self.syntax, REF_KW).is_some()
    }
    pub fn is_unsigned(&self) -> bool {
        token(&self.syntax, UNSIGNED_KW).is_some()
    }
    pub fn type_args(&self) -> impl Iterator<Item = TypeRef> {
        child::<TypeArgs>(&self.syntax).into_iter().flat_map(|a| children(&a.syntax).collect::<Vec<_>>())
    }
    /// Number of `[]` suffixes.
    pub fn array_dims(&self) -> usize {
        self.syntax.children_with_tokens().filter(|e| e.kind() == L_BRACK).count()
    }
}

// ---------------------------------------------------------------- diagrams

ast_node!(ClassDiagram, CLASS_DIAGRAM);
ast_node!(ActivityDiagram, ACTIVITY_DIAGRAM);
ast_node!(ComponentDiagram, COMPONENT_DIAGRAM);
ast_node!(ComponentInstanceDiagram, COMPONENT_INSTANCE_DIAGRAM);
ast_enum!(
    /// A diagram of any kind.
    Diagram { ClassDiagram, ActivityDiagram, ComponentDiagram, ComponentInstanceDiagram }
);

impl HasName for ClassDiagram {}
impl HasName for ActivityDiagram {}
impl HasName for ComponentDiagram {}
impl HasName for ComponentInstanceDiagram {}

impl Diagram {
    pub fn name(&self) -> Option<Name> {
        child(self.syntax())
    }
}

// ---------------------------------------------------------------- class diagrams

ast_node!(Class, CLASS);
ast_node!(Interface, INTERFACE);
ast_node!(Enum, ENUM);
ast_node!(EnumValue, ENUM_VALUE);
ast_node!(
    /// `attribute Name { fields }`: a definition of generator meta-information.
    AttributeDef, ATTRIBUTE_DEF
);
ast_node!(TemplateParams, TEMPLATE_PARAMS);
ast_node!(TemplateParam, TEMPLATE_PARAM);
ast_node!(ExtendsClause, EXTENDS_CLAUSE);
ast_node!(ImplementsClause, IMPLEMENTS_CLAUSE);
ast_node!(MemberList, MEMBER_LIST);
ast_node!(Field, FIELD);
ast_node!(Method, METHOD);
ast_node!(ParamList, PARAM_LIST);
ast_node!(Param, PARAM);
ast_node!(
    /// `self aggregation [0 .. *] subImages : Image;`
    Association, ASSOCIATION
);
ast_node!(Multiplicity, MULTIPLICITY);
ast_enum!(
    /// A type declared in a class diagram.
    TypeDecl { Class, Interface, Enum, AttributeDef }
);
ast_enum!(
    /// A member of a class, interface or attribute.
    Member { Field, Method, Association }
);

impl ClassDiagram {
    pub fn imports(&self) -> impl Iterator<Item = Import> {
        children(&self.syntax)
    }
    pub fn type_decls(&self) -> impl Iterator<Item = TypeDecl> {
        children(&self.syntax)
    }
    /// Nested diagrams (packages).
    pub fn diagrams(&self) -> impl Iterator<Item = Diagram> {
        children(&self.syntax)
    }
}

impl TypeDecl {
    pub fn name(&self) -> Option<Name> {
        child(self.syntax())
    }
    pub fn members(&self) -> impl Iterator<Item = Member> {
        child::<MemberList>(self.syntax()).into_iter().flat_map(|l| l.members().collect::<Vec<_>>())
    }
}

/// The kind of class: plain or one of the component kinds of chapter 11.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClassKind {
    Class,
    Source,
    Filter,
    Sink,
}

impl HasName for Class {}
impl HasModifiers for Class {}
impl Class {
    pub fn kind(&self) -> ClassKind {
        self.syntax
            .children_with_tokens()
            .find_map(|e| match e.kind() {
                SOURCE_KW => Some(ClassKind::Source),
                FILTER_KW => Some(ClassKind::Filter),
                SINK_KW => Some(ClassKind::Sink),
                CLASS_KW => Some(ClassKind::Class),
                _ => None,
            })
            .unwrap_or(ClassKind::Class)
    }
    pub fn is_abstract(&self) -> bool {
        self.has_modifier(ABSTRACT_KW)
    }
    pub fn template_params(&self) -> impl Iterator<Item = TemplateParam> {
        child::<TemplateParams>(&self.syntax).into_iter().flat_map(|t| t.params().collect::<Vec<_>>())
    }
    pub fn extends(&self) -> impl Iterator<Item = TypeRef> {
        child::<ExtendsClause>(&self.syntax).into_iter().flat_map(|c| c.types().collect::<Vec<_>>())
    }
    pub fn implements(&self) -> impl Iterator<Item = TypeRef> {
        child::<ImplementsClause>(&self.syntax).into_iter().flat_map(|c| c.types().collect::<Vec<_>>())
    }
    pub fn members(&self) -> impl Iterator<Item = Member> {
        child::<MemberList>(&self.syntax).into_iter().flat_map(|l| l.members().collect::<Vec<_>>())
    }
}

/// The role of an interface with respect to component ports (chapter 11.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InterfaceRole {
    Plain,
    Provider,
    Processor,
}

impl HasName for Interface {}
impl HasModifiers for Interface {}
impl Interface {
    pub fn role(&self) -> InterfaceRole {
        if token(&self.syntax, PROVIDER_KW).is_some() {
            InterfaceRole::Provider
        } else if token(&self.syntax, PROCESSOR_KW).is_some() {
            InterfaceRole::Processor
        } else {
            InterfaceRole::Plain
        }
    }
    pub fn template_params(&self) -> impl Iterator<Item = TemplateParam> {
        child::<TemplateParams>(&self.syntax).into_iter().flat_map(|t| t.params().collect::<Vec<_>>())
    }
    pub fn extends(&self) -> impl Iterator<Item = TypeRef> {
        child::<ExtendsClause>(&self.syntax).into_iter().flat_map(|c| c.types().collect::<Vec<_>>())
    }
    pub fn members(&self) -> impl Iterator<Item = Member> {
        child::<MemberList>(&self.syntax).into_iter().flat_map(|l| l.members().collect::<Vec<_>>())
    }
}

impl HasName for Enum {}
impl HasModifiers for Enum {}
impl Enum {
    pub fn values(&self) -> impl Iterator<Item = EnumValue> {
        children(&self.syntax)
    }
}

impl HasName for EnumValue {}
impl HasModifiers for EnumValue {}
impl EnumValue {
    pub fn value(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl HasName for AttributeDef {}
impl HasModifiers for AttributeDef {}
impl AttributeDef {
    pub fn members(&self) -> impl Iterator<Item = Member> {
        child::<MemberList>(&self.syntax).into_iter().flat_map(|l| l.members().collect::<Vec<_>>())
    }
}

impl HasName for TemplateParam {}
impl TemplateParams {
    pub fn params(&self) -> impl Iterator<Item = TemplateParam> {
        children(&self.syntax)
    }
}
impl ExtendsClause {
    pub fn types(&self) -> impl Iterator<Item = TypeRef> {
        children(&self.syntax)
    }
}
impl ImplementsClause {
    pub fn types(&self) -> impl Iterator<Item = TypeRef> {
        children(&self.syntax)
    }
}
impl MemberList {
    pub fn members(&self) -> impl Iterator<Item = Member> {
        children(&self.syntax)
    }
}

impl HasName for Field {}
impl HasModifiers for Field {}
impl Field {
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn initializer(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl HasName for Method {}
impl HasModifiers for Method {}
impl Method {
    pub fn return_type(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn params(&self) -> impl Iterator<Item = Param> {
        child::<ParamList>(&self.syntax).into_iter().flat_map(|l| l.params().collect::<Vec<_>>())
    }
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Block> {
        child(&self.syntax)
    }
}

impl ParamList {
    pub fn params(&self) -> impl Iterator<Item = Param> {
        children(&self.syntax)
    }
}

impl HasName for Param {}
impl HasModifiers for Param {}
impl Param {
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
}

/// Kind of an association end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AssociationKind {
    Plain,
    Aggregation,
    Composition,
}

impl HasName for Association {}
impl HasModifiers for Association {}
impl Association {
    pub fn kind(&self) -> AssociationKind {
        if token(&self.syntax, AGGREGATION_KW).is_some() {
            AssociationKind::Aggregation
        } else if token(&self.syntax, COMPOSITION_KW).is_some() {
            AssociationKind::Composition
        } else {
            AssociationKind::Plain
        }
    }
    pub fn target(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    /// Multiplicity of this end (before the role name).
    pub fn own_multiplicity(&self) -> Option<Multiplicity> {
        let name_start = self.name()?.syntax.text_range().start();
        children::<Multiplicity>(&self.syntax).find(|m| m.syntax.text_range().end() <= name_start)
    }
    /// Multiplicity of the other end (after the type), for bidirectional associations.
    pub fn target_multiplicity(&self) -> Option<Multiplicity> {
        let type_end = self.target()?.syntax.text_range().end();
        children::<Multiplicity>(&self.syntax).find(|m| m.syntax.text_range().start() >= type_end)
    }
}

impl Multiplicity {
    /// The bounds as written: `("0", Some("*"))` for `[0 .. *]`.
    pub fn bounds(&self) -> (Option<String>, Option<String>) {
        let mut bounds = self
            .syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .filter(|t| matches!(t.kind(), INT_NUMBER | STAR))
            .map(|t| t.text().to_string());
        (bounds.next(), bounds.next())
    }
}

// ---------------------------------------------------------------- activity diagrams

ast_node!(OwnerClause, OWNER_CLAUSE);
ast_node!(
    /// An entry of the variable section.
    Variable, VARIABLE
);
ast_node!(Swimlane, SWIMLANE);
ast_node!(NodeBody, NODE_BODY);
ast_node!(LoopHeader, LOOP_HEADER);
ast_node!(LoopSection, LOOP_SECTION);
ast_node!(Transition, TRANSITION);
ast_node!(Guard, GUARD);
ast_node!(ArgList, ARG_LIST);

impl ActivityDiagram {
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
    pub fn params(&self) -> impl Iterator<Item = Param> {
        self.param_list().into_iter().flat_map(|l| l.params().collect::<Vec<_>>())
    }
    pub fn owner(&self) -> Option<Path> {
        child::<OwnerClause>(&self.syntax).and_then(|o| o.path())
    }
    pub fn imports(&self) -> impl Iterator<Item = Import> {
        children(&self.syntax)
    }
    pub fn variables(&self) -> impl Iterator<Item = Variable> {
        children(&self.syntax)
    }
    /// `var`-style declarations in the variable section.
    pub fn var_decls(&self) -> impl Iterator<Item = VarDecl> {
        children(&self.syntax)
    }
    pub fn swimlanes(&self) -> impl Iterator<Item = Swimlane> {
        children(&self.syntax)
    }
    /// Nodes written outside any swimlane.
    pub fn nodes(&self) -> impl Iterator<Item = ActivityNode> {
        children(&self.syntax)
    }
}

impl OwnerClause {
    pub fn path(&self) -> Option<Path> {
        child(&self.syntax)
    }
}

impl HasName for Variable {}
impl HasModifiers for Variable {}
impl Variable {
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn initializer(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl HasName for Swimlane {}
impl Swimlane {
    pub fn owner(&self) -> Option<Path> {
        child::<OwnerClause>(&self.syntax).and_then(|o| o.path())
    }
    pub fn nodes(&self) -> impl Iterator<Item = ActivityNode> {
        children(&self.syntax)
    }
}

/// The kind of an activity node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeKind {
    Start,
    Final,
    Action,
    Decision,
    Fork,
    Join,
    Loop,
    LoopWindow,
    Calc,
    CalcRange,
}

/// Any activity node (`start`, `action`, `calc`, …).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ActivityNode {
    pub(crate) syntax: SyntaxNode,
}

impl AstNode for ActivityNode {
    fn can_cast(kind: SyntaxKind) -> bool {
        node_kind(kind).is_some()
    }
    fn cast(node: SyntaxNode) -> Option<Self> {
        Self::can_cast(node.kind()).then_some(ActivityNode { syntax: node })
    }
    fn syntax(&self) -> &SyntaxNode {
        &self.syntax
    }
}

fn node_kind(kind: SyntaxKind) -> Option<NodeKind> {
    Some(match kind {
        START_NODE => NodeKind::Start,
        FINAL_NODE => NodeKind::Final,
        ACTION_NODE => NodeKind::Action,
        DECISION_NODE => NodeKind::Decision,
        FORK_NODE => NodeKind::Fork,
        JOIN_NODE => NodeKind::Join,
        LOOP_NODE => NodeKind::Loop,
        LOOP_WINDOW_NODE => NodeKind::LoopWindow,
        CALC_NODE => NodeKind::Calc,
        CALC_RANGE_NODE => NodeKind::CalcRange,
        _ => return None,
    })
}

impl HasName for ActivityNode {}
impl ActivityNode {
    pub fn kind(&self) -> NodeKind {
        node_kind(self.syntax.kind()).unwrap_or(NodeKind::Action)
    }
    pub fn param_list(&self) -> Option<ParamList> {
        child(&self.syntax)
    }
    pub fn params(&self) -> impl Iterator<Item = Param> {
        self.param_list().into_iter().flat_map(|l| l.params().collect::<Vec<_>>())
    }
    /// `(setup; test; increment)` of loop and loopWindow nodes.
    pub fn loop_header(&self) -> Option<LoopHeader> {
        child(&self.syntax)
    }
    /// `final f return expr`
    pub fn return_value(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<NodeBody> {
        child(&self.syntax)
    }
    pub fn statements(&self) -> impl Iterator<Item = Stmt> {
        self.body().into_iter().flat_map(|b| b.statements().collect::<Vec<_>>())
    }
    pub fn transitions(&self) -> impl Iterator<Item = Transition> {
        self.body().into_iter().flat_map(|b| b.transitions().collect::<Vec<_>>())
    }
}

impl NodeBody {
    pub fn statements(&self) -> impl Iterator<Item = Stmt> {
        children(&self.syntax)
    }
    pub fn transitions(&self) -> impl Iterator<Item = Transition> {
        children(&self.syntax)
    }
}

impl LoopHeader {
    pub fn sections(&self) -> impl Iterator<Item = LoopSection> {
        children(&self.syntax)
    }
}

/// One part of a loop section: a declaration or an expression.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LoopPart {
    Decl(VarDecl),
    Expr(Expr),
}

impl LoopSection {
    pub fn parts(&self) -> impl Iterator<Item = LoopPart> {
        self.syntax
            .children()
            .filter_map(|n| VarDecl::cast(n.clone()).map(LoopPart::Decl).or_else(|| Expr::cast(n).map(LoopPart::Expr)))
    }
}

impl Transition {
    /// `None` for an unguarded `=>`; `Some(guard)` also for the empty guard `[] =>`.
    pub fn guard(&self) -> Option<Guard> {
        child(&self.syntax)
    }
    pub fn target(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn arg_list(&self) -> Option<ArgList> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        self.arg_list().into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}

impl Guard {
    /// The condition; `None` for the empty guard `[]`.
    pub fn condition(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl ArgList {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        children(&self.syntax)
    }
}

// ---------------------------------------------------------------- statements

ast_node!(Block, BLOCK);
ast_node!(VarDecl, VAR_DECL);
ast_node!(ExprStmt, EXPR_STMT);
ast_node!(EmptyStmt, EMPTY_STMT);
ast_node!(IfStmt, IF_STMT);
ast_node!(ElseBranch, ELSE_BRANCH);
ast_node!(LoopStmt, LOOP_STMT);
ast_node!(DoLoopStmt, DO_LOOP_STMT);
ast_node!(ForStmt, FOR_STMT);
ast_node!(SwitchStmt, SWITCH_STMT);
ast_node!(SwitchCase, SWITCH_CASE);
ast_node!(ReturnStmt, RETURN_STMT);
ast_node!(BreakStmt, BREAK_STMT);
ast_node!(ContinueStmt, CONTINUE_STMT);
ast_node!(LoopWindowStmt, LOOP_WINDOW_STMT);
ast_node!(LoopWindowDim, LOOP_WINDOW_DIM);
ast_enum!(
    /// A statement of the expression language.
    Stmt {
        Block, VarDecl, ExprStmt, EmptyStmt, IfStmt, LoopStmt, DoLoopStmt, ForStmt, SwitchStmt,
        ReturnStmt, BreakStmt, ContinueStmt, LoopWindowStmt,
    }
);

impl Block {
    pub fn statements(&self) -> impl Iterator<Item = Stmt> {
        children(&self.syntax)
    }
}

impl HasName for VarDecl {}
impl HasModifiers for VarDecl {}
impl VarDecl {
    /// `const` declarations cannot be assigned again.
    pub fn is_const(&self) -> bool {
        token(&self.syntax, CONST_KW).is_some() || self.has_modifier(CONST_KW)
    }
    pub fn is_ref(&self) -> bool {
        self.has_modifier(REF_KW) || self.type_ref().is_some_and(|t| t.is_ref())
    }
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn initializer(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl ExprStmt {
    pub fn expr(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl IfStmt {
    pub fn condition(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn then_branch(&self) -> Option<Stmt> {
        child(&self.syntax)
    }
    pub fn else_branch(&self) -> Option<Stmt> {
        child::<ElseBranch>(&self.syntax).and_then(|e| child(&e.syntax))
    }
}

impl LoopStmt {
    pub fn condition(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Stmt> {
        child(&self.syntax)
    }
}

impl DoLoopStmt {
    pub fn body(&self) -> Option<Stmt> {
        child(&self.syntax)
    }
    pub fn condition(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl ForStmt {
    /// `init : step : condition`, in the order written.
    pub fn sections(&self) -> Vec<LoopPart> {
        self.syntax
            .children()
            .filter_map(|n| VarDecl::cast(n.clone()).map(LoopPart::Decl).or_else(|| Expr::cast(n).map(LoopPart::Expr)))
            .collect()
    }
    pub fn body(&self) -> Option<Stmt> {
        child(&self.syntax)
    }
}

impl SwitchStmt {
    pub fn scrutinee(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn cases(&self) -> impl Iterator<Item = SwitchCase> {
        children(&self.syntax)
    }
}

impl SwitchCase {
    /// `None` for `default`.
    pub fn label(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn is_default(&self) -> bool {
        token(&self.syntax, DEFAULT_KW).is_some()
    }
    pub fn statements(&self) -> impl Iterator<Item = Stmt> {
        children(&self.syntax)
    }
}

impl ReturnStmt {
    pub fn value(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl LoopWindowStmt {
    /// 2 for `loopwindow2D`, 3 for `loopwindow3D`.
    pub fn dimensions(&self) -> usize {
        if token(&self.syntax, LOOPWINDOW3D_KW).is_some() {
            3
        } else {
            2
        }
    }
    pub fn ranges(&self) -> impl Iterator<Item = LoopWindowDim> {
        children(&self.syntax)
    }
    pub fn body(&self) -> Option<Block> {
        child(&self.syntax)
    }
}

impl LoopWindowDim {
    pub fn start(&self) -> Option<LoopPart> {
        self.syntax
            .children()
            .find_map(|n| VarDecl::cast(n.clone()).map(LoopPart::Decl).or_else(|| Expr::cast(n).map(LoopPart::Expr)))
    }
    pub fn end(&self) -> Option<Expr> {
        children::<Expr>(&self.syntax).last().filter(|_| self.syntax.children().count() == 2)
    }
}

// ---------------------------------------------------------------- expressions

ast_node!(Literal, LITERAL);
ast_node!(NameExpr, NAME_EXPR);
ast_node!(ThisExpr, THIS_EXPR);
ast_node!(ParenExpr, PAREN_EXPR);
ast_node!(BinExpr, BIN_EXPR);
ast_node!(PrefixExpr, PREFIX_EXPR);
ast_node!(PostfixExpr, POSTFIX_EXPR);
ast_node!(TernaryExpr, TERNARY_EXPR);
ast_node!(
    /// `(float)x`
    CastExpr, CAST_EXPR
);
ast_node!(
    /// `x as ref void`
    AsExpr, AS_EXPR
);
ast_node!(CallExpr, CALL_EXPR);
ast_node!(IndexExpr, INDEX_EXPR);
ast_node!(MemberExpr, MEMBER_EXPR);
ast_node!(
    /// `QImageFormat::Format_ARGB32`
    ScopeExpr, SCOPE_EXPR
);
ast_node!(NewExpr, NEW_EXPR);
ast_node!(
    /// `call behavior AdFilterMean(…)`
    CallBehaviorExpr, CALL_BEHAVIOR_EXPR
);
ast_node!(
    /// `call Filter::filterBilateral(…)`
    CallMethodExpr, CALL_METHOD_EXPR
);
ast_node!(
    /// `call interface I.m(…)` or `call I.m(…)`
    CallInterfaceExpr, CALL_INTERFACE_EXPR
);
ast_enum!(
    /// An expression.
    Expr {
        Literal, NameExpr, ThisExpr, ParenExpr, BinExpr, PrefixExpr, PostfixExpr, TernaryExpr,
        CastExpr, AsExpr, CallExpr, IndexExpr, MemberExpr, ScopeExpr, NewExpr, CallBehaviorExpr,
        CallMethodExpr, CallInterfaceExpr,
    }
);

/// The operator token of an operator node.
fn operator(node: &SyntaxNode) -> Option<SyntaxToken> {
    node.children_with_tokens().filter_map(|e| e.into_token()).find(|t| !t.kind().is_trivia())
}

impl Literal {
    pub fn token(&self) -> Option<SyntaxToken> {
        self.syntax.first_token()
    }
}

impl NameExpr {
    pub fn name_ref(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl ParenExpr {
    pub fn expr(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl BinExpr {
    pub fn lhs(&self) -> Option<Expr> {
        children(&self.syntax).next()
    }
    pub fn rhs(&self) -> Option<Expr> {
        children(&self.syntax).nth(1)
    }
    /// The operator token (`+`, `==`, `=`, `>>=`, …).
    pub fn op(&self) -> Option<SyntaxToken> {
        self.syntax.children_with_tokens().filter_map(|e| e.into_token()).find(|t| !t.kind().is_trivia())
    }
    pub fn is_assignment(&self) -> bool {
        self.op().is_some_and(|t| {
            matches!(
                t.kind(),
                EQ | PLUSEQ | MINUSEQ | STAREQ | SLASHEQ | PERCENTEQ | AMPEQ | PIPEEQ | CARETEQ | SHLEQ | SHREQ
            )
        })
    }
}

impl PrefixExpr {
    pub fn op(&self) -> Option<SyntaxToken> {
        operator(&self.syntax)
    }
    pub fn operand(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl PostfixExpr {
    pub fn op(&self) -> Option<SyntaxToken> {
        operator(&self.syntax)
    }
    pub fn operand(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl TernaryExpr {
    pub fn condition(&self) -> Option<Expr> {
        children(&self.syntax).next()
    }
    pub fn then_expr(&self) -> Option<Expr> {
        children(&self.syntax).nth(1)
    }
    pub fn else_expr(&self) -> Option<Expr> {
        children(&self.syntax).nth(2)
    }
}

impl CastExpr {
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn operand(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl AsExpr {
    pub fn operand(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
}

impl CallExpr {
    pub fn callee(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn arg_list(&self) -> Option<ArgList> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        self.arg_list().into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}

impl IndexExpr {
    pub fn base(&self) -> Option<Expr> {
        children(&self.syntax).next()
    }
    pub fn index(&self) -> Option<Expr> {
        children(&self.syntax).nth(1)
    }
}

impl MemberExpr {
    pub fn receiver(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn member(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl ScopeExpr {
    pub fn scope(&self) -> Option<Expr> {
        child(&self.syntax)
    }
    pub fn member(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl NewExpr {
    pub fn type_ref(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    /// Constructor arguments of `new T(…)`.
    pub fn arg_list(&self) -> Option<ArgList> {
        child(&self.syntax)
    }
    /// Size of `new T[n]`.
    pub fn array_size(&self) -> Option<Expr> {
        child(&self.syntax)
    }
}

impl CallBehaviorExpr {
    pub fn behavior(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        child::<ArgList>(&self.syntax).into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}

impl CallMethodExpr {
    pub fn class(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn method(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        child::<ArgList>(&self.syntax).into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}

impl CallInterfaceExpr {
    /// `I.m` as one path: all segments but the last name the interface, the last the method.
    pub fn path(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        child::<ArgList>(&self.syntax).into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}

// ---------------------------------------------------------------- components

ast_node!(Component, COMPONENT);
ast_node!(Port, PORT);
ast_node!(Connector, CONNECTOR);
ast_node!(Connection, CONNECTION);
ast_node!(ComponentInstance, COMPONENT_INSTANCE);
ast_node!(PortInstance, PORT_INSTANCE);
ast_node!(CidConnector, CID_CONNECTOR);
ast_node!(Binding, BINDING);

impl ComponentDiagram {
    pub fn imports(&self) -> impl Iterator<Item = Import> {
        children(&self.syntax)
    }
    pub fn components(&self) -> impl Iterator<Item = Component> {
        children(&self.syntax)
    }
    pub fn diagrams(&self) -> impl Iterator<Item = Diagram> {
        children(&self.syntax)
    }
}

impl Component {
    pub fn kind(&self) -> ClassKind {
        match self.syntax.first_token().map(|t| t.kind()) {
            Some(SOURCE_KW) => ClassKind::Source,
            Some(FILTER_KW) => ClassKind::Filter,
            Some(SINK_KW) => ClassKind::Sink,
            _ => ClassKind::Class,
        }
    }
    /// The component class it is built on.
    pub fn class(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn ports(&self) -> impl Iterator<Item = Port> {
        children(&self.syntax)
    }
    pub fn connections(&self) -> impl Iterator<Item = Connection> {
        children(&self.syntax)
    }
    pub fn components(&self) -> impl Iterator<Item = Component> {
        children(&self.syntax)
    }
}

impl HasName for Port {}
impl Port {
    pub fn is_async(&self) -> bool {
        token(&self.syntax, ASYNC_KW).is_some()
    }
    pub fn is_buffered(&self) -> bool {
        token(&self.syntax, BUFFERED_KW).is_some()
    }
    pub fn connectors(&self) -> impl Iterator<Item = Connector> {
        children(&self.syntax)
    }
}

/// Direction of a connector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConnectorRole {
    Provider,
    Processor,
}

fn connector_role(node: &SyntaxNode) -> Option<ConnectorRole> {
    match node.first_token()?.kind() {
        PROVIDER_KW => Some(ConnectorRole::Provider),
        PROCESSOR_KW => Some(ConnectorRole::Processor),
        _ => None,
    }
}

impl HasName for Connector {}
impl Connector {
    pub fn role(&self) -> Option<ConnectorRole> {
        connector_role(&self.syntax)
    }
    pub fn interface(&self) -> Option<Path> {
        child(&self.syntax)
    }
}

/// `[Name source a.b ==> target c.d]`, shared by connections and bindings.
pub trait HasEnds: AstNode {
    /// The connection's own name, if written.
    fn connection_name(&self) -> Option<Name> {
        child(self.syntax())
    }
    fn source(&self) -> Option<Path> {
        children(self.syntax()).next()
    }
    fn target(&self) -> Option<Path> {
        let has_arrow = token(self.syntax(), LONG_FAT_ARROW)?;
        children::<Path>(self.syntax()).find(|p| p.syntax.text_range().start() >= has_arrow.text_range().end())
    }
}

impl HasEnds for Connection {}
impl HasEnds for Binding {}

impl ComponentInstanceDiagram {
    pub fn imports(&self) -> impl Iterator<Item = Import> {
        children(&self.syntax)
    }
    pub fn instances(&self) -> impl Iterator<Item = ComponentInstance> {
        children(&self.syntax)
    }
    /// Port instances written at diagram level (the flat form of Listing 28).
    pub fn port_instances(&self) -> impl Iterator<Item = PortInstance> {
        children(&self.syntax)
    }
    /// Bindings written at diagram level.
    pub fn bindings(&self) -> impl Iterator<Item = Binding> {
        children(&self.syntax)
    }
}

impl HasName for ComponentInstance {}
impl ComponentInstance {
    pub fn component(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn field_values(&self) -> impl Iterator<Item = NamedArg> {
        child::<NamedArgList>(&self.syntax).into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
    pub fn port_instances(&self) -> impl Iterator<Item = PortInstance> {
        children(&self.syntax)
    }
    pub fn bindings(&self) -> impl Iterator<Item = Binding> {
        children(&self.syntax)
    }
}

impl HasName for PortInstance {}
impl PortInstance {
    /// The port of the component this instantiates.
    pub fn port(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn connectors(&self) -> impl Iterator<Item = CidConnector> {
        children(&self.syntax)
    }
}

impl HasName for CidConnector {}
impl CidConnector {
    pub fn role(&self) -> Option<ConnectorRole> {
        connector_role(&self.syntax)
    }
    pub fn interface(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn field_values(&self) -> impl Iterator<Item = NamedArg> {
        child::<NamedArgList>(&self.syntax).into_iter().flat_map(|l| l.args().collect::<Vec<_>>())
    }
}
