//! Hand-written accessors: those that need more than "the child of this kind" (position, order,
//! text, a keyword's meaning), and convenience accessors that reach through a list node.

use super::{support, AstNode, HasModifiers, HasName};
use super::{
    ActivityDiagram, ActivityNode, ArgList, Association, AttributeDef, AttributeUse, BinExpr, Binding,
    CallBehaviorExpr, CallExpr, CallInterfaceExpr, CallMethodExpr, CidConnector, Class, Component, ComponentInstance,
    Connection, Connector, Expr, ForStmt, IfStmt, Import, IndexExpr, Interface, LoopHeader, LoopSection, LoopWindowDim,
    LoopWindowStmt, Member, Method, Modifiers, Multiplicity, Name, NameRef, NamedArg, NodeBody, Param, ParamList, Path,
    Port, Stmt, SwitchCase, TemplateParam, TernaryExpr, Transition, TypeDecl, TypeRef, VarDecl,
};
use crate::syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken};

// ---------------------------------------------------------------- names and paths

impl Name {
    pub fn text(&self) -> String {
        ident_text(&self.syntax)
    }
}

impl NameRef {
    pub fn text(&self) -> String {
        ident_text(&self.syntax)
    }
}

/// The text of a name's identifier, read from the green tree (no syntax token is made: names
/// are read at every declaration and use of every check).
fn ident_text(name: &SyntaxNode) -> String {
    let ident = rowan::SyntaxKind::from(IDENT);
    let green = name.green();
    let token = green.children().find_map(|child| child.into_token().filter(|t| t.kind() == ident));
    token.map(|t| t.text().to_string()).unwrap_or_default()
}

impl Path {
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
        if let Some(lit) = self.literal() {
            return lit.token().map(ImportTarget::Header);
        }
        let path = self.path()?;
        Some(if self.star_token().is_some() { ImportTarget::Wildcard(path) } else { ImportTarget::Name(path) })
    }
}

impl AttributeUse {
    pub fn args(&self) -> impl Iterator<Item = NamedArg> {
        self.named_arg_list().into_iter().flat_map(|l| l.args())
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

impl TypeRef {
    pub fn is_ref(&self) -> bool {
        self.ref_token().is_some()
    }
    pub fn is_unsigned(&self) -> bool {
        self.unsigned_token().is_some()
    }
    pub fn type_args(&self) -> impl Iterator<Item = TypeRef> {
        self.type_arg_list().into_iter().flat_map(|a| a.type_refs())
    }
    /// Number of `[]` suffixes.
    pub fn array_dims(&self) -> usize {
        self.syntax.children_with_tokens().filter(|e| e.kind() == L_BRACK).count()
    }
}

// ---------------------------------------------------------------- class diagrams

impl TypeDecl {
    pub fn members(&self) -> impl Iterator<Item = Member> {
        support::child::<super::MemberList>(self.syntax()).into_iter().flat_map(|l| l.members())
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

/// The class kind a `class`, `source`, `filter` or `sink` keyword names.
fn class_kind(keyword: SyntaxKind) -> Option<ClassKind> {
    match keyword {
        SOURCE_KW => Some(ClassKind::Source),
        FILTER_KW => Some(ClassKind::Filter),
        SINK_KW => Some(ClassKind::Sink),
        CLASS_KW => Some(ClassKind::Class),
        _ => None,
    }
}

impl Class {
    pub fn kind(&self) -> ClassKind {
        self.syntax.children_with_tokens().find_map(|e| class_kind(e.kind())).unwrap_or(ClassKind::Class)
    }
    pub fn is_abstract(&self) -> bool {
        self.has_modifier(ABSTRACT_KW)
    }
    pub fn template_params(&self) -> impl Iterator<Item = TemplateParam> {
        self.template_param_list().into_iter().flat_map(|t| t.params())
    }
    pub fn extends(&self) -> impl Iterator<Item = TypeRef> {
        self.extends_clause().into_iter().flat_map(|c| c.types())
    }
    pub fn implements(&self) -> impl Iterator<Item = TypeRef> {
        self.implements_clause().into_iter().flat_map(|c| c.types())
    }
    pub fn members(&self) -> impl Iterator<Item = Member> {
        self.member_list().into_iter().flat_map(|l| l.members())
    }
}

/// The role of an interface with respect to component ports (chapter 11.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InterfaceRole {
    Plain,
    Provider,
    Processor,
}

impl Interface {
    pub fn role(&self) -> InterfaceRole {
        if self.provider_token().is_some() {
            InterfaceRole::Provider
        } else if self.processor_token().is_some() {
            InterfaceRole::Processor
        } else {
            InterfaceRole::Plain
        }
    }
    pub fn template_params(&self) -> impl Iterator<Item = TemplateParam> {
        self.template_param_list().into_iter().flat_map(|t| t.params())
    }
    pub fn extends(&self) -> impl Iterator<Item = TypeRef> {
        self.extends_clause().into_iter().flat_map(|c| c.types())
    }
    pub fn members(&self) -> impl Iterator<Item = Member> {
        self.member_list().into_iter().flat_map(|l| l.members())
    }
}

impl AttributeDef {
    pub fn members(&self) -> impl Iterator<Item = Member> {
        self.member_list().into_iter().flat_map(|l| l.members())
    }
}

impl Method {
    pub fn params(&self) -> impl Iterator<Item = Param> {
        self.param_list().into_iter().flat_map(|l| l.params())
    }
}

/// Kind of an association end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AssociationKind {
    Plain,
    Aggregation,
    Composition,
}

impl Association {
    pub fn kind(&self) -> AssociationKind {
        if self.aggregation_token().is_some() {
            AssociationKind::Aggregation
        } else if self.composition_token().is_some() {
            AssociationKind::Composition
        } else {
            AssociationKind::Plain
        }
    }
    /// Multiplicity of this end (before the role name).
    pub fn own_multiplicity(&self) -> Option<Multiplicity> {
        let name_start = self.name()?.syntax.text_range().start();
        support::children::<Multiplicity>(&self.syntax).find(|m| m.syntax.text_range().end() <= name_start)
    }
    /// Multiplicity of the other end (after the type), for bidirectional associations.
    pub fn target_multiplicity(&self) -> Option<Multiplicity> {
        let type_end = self.target()?.syntax.text_range().end();
        support::children::<Multiplicity>(&self.syntax).find(|m| m.syntax.text_range().start() >= type_end)
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

impl ActivityDiagram {
    pub fn params(&self) -> impl Iterator<Item = Param> {
        self.param_list().into_iter().flat_map(|l| l.params())
    }
    pub fn owner(&self) -> Option<Path> {
        self.owner_clause().and_then(|o| o.path())
    }
    /// The nodes of the diagram's flow: the swimlanes' in order, then those outside any
    /// swimlane; not the nodes nested in them ([`ActivityNode::nested_nodes`]).
    pub fn all_nodes(&self) -> impl Iterator<Item = ActivityNode> {
        self.swimlanes().flat_map(|lane| lane.nodes()).chain(self.nodes())
    }
    /// Every node, nested ones too, each before the nodes it holds.
    pub fn every_node(&self) -> Vec<ActivityNode> {
        self.all_nodes().flat_map(|node| node.and_nested()).collect()
    }
}

impl super::Swimlane {
    pub fn owner(&self) -> Option<Path> {
        self.owner_clause().and_then(|o| o.path())
    }
}

impl ActivityNode {
    pub fn param_list(&self) -> Option<ParamList> {
        support::child(self.syntax())
    }
    pub fn params(&self) -> impl Iterator<Item = Param> {
        self.param_list().into_iter().flat_map(|l| l.params())
    }
    /// `(setup; test; increment)` of loop and loopWindow nodes.
    pub fn loop_header(&self) -> Option<LoopHeader> {
        support::child(self.syntax())
    }
    /// `final f return expr`
    pub fn return_value(&self) -> Option<Expr> {
        support::child(self.syntax())
    }
    pub fn body(&self) -> Option<NodeBody> {
        support::child(self.syntax())
    }
    pub fn statements(&self) -> impl Iterator<Item = Stmt> {
        self.body().into_iter().flat_map(|b| b.statements())
    }
    pub fn transitions(&self) -> impl Iterator<Item = Transition> {
        self.body().into_iter().flat_map(|b| b.transitions())
    }
    /// The nodes of the flow the node holds (a node container, Sec. 9.2.2.3).
    pub fn nested_nodes(&self) -> impl Iterator<Item = ActivityNode> {
        self.body().into_iter().flat_map(|b| b.nodes())
    }
    /// Whether the node may hold nodes (a node container, Sec. 9.2.2.3): loop and conditional
    /// nodes, and actions as UML's structured nodes.
    pub fn may_hold_nodes(&self) -> bool {
        use crate::syntax::NodeKind::*;
        matches!(self.kind(), Action | Decision | Loop | LoopWindow)
    }
    /// The flow the node is in, as a key: the offset of the node that holds it; `None` for the
    /// diagram's own flow.
    pub fn flow(&self) -> Option<rowan::TextSize> {
        self.container().map(|c| c.syntax().text_range().start())
    }
    /// The node that holds this one, if it is nested.
    pub fn container(&self) -> Option<ActivityNode> {
        let parent = self.syntax().parent().filter(|p| p.kind() == NODE_BODY)?;
        parent.parent().and_then(ActivityNode::cast)
    }
    /// The node and every node nested in it, each before the nodes it holds. Walks only the
    /// node's children and its body's: nothing is collected.
    pub fn and_nested(&self) -> super::walk::AndNested {
        super::walk::AndNested::new(self)
    }
}

/// One part of a loop section, a `for` header or a window range: a declaration or an expression.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LoopPart {
    Decl(VarDecl),
    Expr(Expr),
}

impl LoopPart {
    fn cast(node: SyntaxNode) -> Option<LoopPart> {
        VarDecl::cast(node.clone()).map(LoopPart::Decl).or_else(|| Expr::cast(node).map(LoopPart::Expr))
    }
}

impl LoopSection {
    pub fn parts(&self) -> impl Iterator<Item = LoopPart> {
        self.syntax.children().filter_map(LoopPart::cast)
    }
}

impl Transition {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        self.arg_list().into_iter().flat_map(|l| l.args())
    }
}

// ---------------------------------------------------------------- statements

impl VarDecl {
    /// `const` declarations cannot be assigned again.
    pub fn is_const(&self) -> bool {
        self.const_token().is_some() || self.has_modifier(CONST_KW)
    }
    pub fn is_ref(&self) -> bool {
        self.has_modifier(REF_KW) || self.type_ref().is_some_and(|t| t.is_ref())
    }
}

impl IfStmt {
    pub fn else_branch(&self) -> Option<Stmt> {
        self.else_clause().and_then(|e| e.stmt())
    }
}

impl ForStmt {
    /// `init : step : condition`, in the order written.
    pub fn sections(&self) -> Vec<LoopPart> {
        let header_end = self.r_paren_token().map(|t| t.text_range().start());
        self.syntax
            .children()
            .take_while(|n| header_end.is_none_or(|end| n.text_range().end() <= end))
            .filter_map(LoopPart::cast)
            .collect()
    }
    /// The statement after the header.
    pub fn body(&self) -> Option<Stmt> {
        let header_end = self.r_paren_token()?.text_range().end();
        support::children::<Stmt>(&self.syntax).find(|s| s.syntax().text_range().start() >= header_end)
    }
}

impl SwitchCase {
    pub fn is_default(&self) -> bool {
        self.default_token().is_some()
    }
}

impl LoopWindowStmt {
    /// 2 for `loopwindow2D`, 3 for `loopwindow3D`.
    pub fn dimensions(&self) -> usize {
        if self.loopwindow3d_token().is_some() {
            3
        } else {
            2
        }
    }
}

impl LoopWindowDim {
    pub fn start(&self) -> Option<LoopPart> {
        self.syntax.children().find_map(LoopPart::cast)
    }
    pub fn end(&self) -> Option<Expr> {
        support::children::<Expr>(&self.syntax).last().filter(|_| self.syntax.children().count() == 2)
    }
    /// `name = first : last`: the window variable's name, its first and its last value; `None`
    /// for a range written otherwise.
    pub fn bounds(&self) -> Option<(String, Expr, Expr)> {
        let Some(LoopPart::Expr(Expr::BinExpr(start))) = self.start() else { return None };
        let (Some(Expr::NameExpr(name)), Some(first), Some(last)) = (start.lhs(), start.rhs(), self.end()) else {
            return None;
        };
        Some((name.name_ref()?.text(), first, last))
    }
}

// ---------------------------------------------------------------- expressions

impl BinExpr {
    pub fn lhs(&self) -> Option<Expr> {
        support::children(&self.syntax).next()
    }
    pub fn rhs(&self) -> Option<Expr> {
        support::children(&self.syntax).nth(1)
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

impl TernaryExpr {
    pub fn condition(&self) -> Option<Expr> {
        support::children(&self.syntax).next()
    }
    pub fn then_expr(&self) -> Option<Expr> {
        support::children(&self.syntax).nth(1)
    }
    pub fn else_expr(&self) -> Option<Expr> {
        support::children(&self.syntax).nth(2)
    }
}

impl IndexExpr {
    pub fn base(&self) -> Option<Expr> {
        support::children(&self.syntax).next()
    }
    pub fn index(&self) -> Option<Expr> {
        support::children(&self.syntax).nth(1)
    }
}

/// The arguments of an argument list, if there is one.
fn args_of(list: Option<ArgList>) -> impl Iterator<Item = Expr> {
    list.into_iter().flat_map(|l| l.args())
}

impl CallExpr {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        args_of(self.arg_list())
    }
}

impl CallBehaviorExpr {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        args_of(self.arg_list())
    }
}

impl CallMethodExpr {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        args_of(self.arg_list())
    }
}

impl CallInterfaceExpr {
    pub fn args(&self) -> impl Iterator<Item = Expr> {
        args_of(self.arg_list())
    }
}

// ---------------------------------------------------------------- components

impl Component {
    pub fn kind(&self) -> ClassKind {
        first_keyword(&self.syntax).and_then(class_kind).unwrap_or(ClassKind::Class)
    }
}

impl Port {
    pub fn is_async(&self) -> bool {
        self.async_token().is_some()
    }
    pub fn is_buffered(&self) -> bool {
        self.buffered_token().is_some()
    }
}

/// Direction of a connector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConnectorRole {
    Provider,
    Processor,
}

impl ConnectorRole {
    /// The keyword that writes it: `provider` or `processor`.
    pub fn keyword(self) -> &'static str {
        match self {
            ConnectorRole::Provider => "provider",
            ConnectorRole::Processor => "processor",
        }
    }
}

/// The kind of a node's first token that is no trivia (a comment above it belongs to it).
fn first_keyword(node: &SyntaxNode) -> Option<SyntaxKind> {
    node.descendants_with_tokens().filter_map(|e| e.into_token()).map(|t| t.kind()).find(|k| !k.is_trivia())
}

fn connector_role(node: &SyntaxNode) -> Option<ConnectorRole> {
    match first_keyword(node)? {
        PROVIDER_KW => Some(ConnectorRole::Provider),
        PROCESSOR_KW => Some(ConnectorRole::Processor),
        _ => None,
    }
}

impl Connector {
    pub fn role(&self) -> Option<ConnectorRole> {
        connector_role(&self.syntax)
    }
}

impl CidConnector {
    pub fn role(&self) -> Option<ConnectorRole> {
        connector_role(&self.syntax)
    }
    pub fn field_values(&self) -> impl Iterator<Item = NamedArg> {
        self.named_arg_list().into_iter().flat_map(|l| l.args())
    }
}

/// `[Name source a.b ==> target c.d]`, shared by connections and bindings.
pub trait HasEnds: AstNode {
    fn source(&self) -> Option<Path> {
        support::children(self.syntax()).next()
    }
    fn target(&self) -> Option<Path> {
        let arrow = support::token(self.syntax(), LONG_FAT_ARROW)?;
        support::children::<Path>(self.syntax()).find(|p| p.syntax.text_range().start() >= arrow.text_range().end())
    }
}

impl HasEnds for Connection {}
impl HasEnds for Binding {}

impl ComponentInstance {
    pub fn field_values(&self) -> impl Iterator<Item = NamedArg> {
        self.named_arg_list().into_iter().flat_map(|l| l.args())
    }
    /// The instance a port instance or binding `member` follows without braces (Listing 28's
    /// flat form); `None` for any other node, or a member inside braces.
    pub fn of_flat_member(member: &SyntaxNode) -> Option<ComponentInstance> {
        if !matches!(member.kind(), PORT_INSTANCE | BINDING) {
            return None;
        }
        member.parent().and_then(ComponentInstance::cast).filter(|i| i.l_curly_token().is_none())
    }
}
