//! Document outline: diagrams → classes, swimlanes, components → members, nodes, ports.

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile},
    syntax::{SyntaxNode, TextRange},
};

/// What a symbol is, for the outline's icons.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SymbolKind {
    Diagram,
    Class,
    Interface,
    Enum,
    EnumValue,
    Attribute,
    Field,
    Method,
    Variable,
    Swimlane,
    Node,
    Component,
    Port,
    Instance,
}

/// One entry of the outline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    pub name: String,
    pub detail: Option<String>,
    pub kind: SymbolKind,
    /// The whole declaration.
    pub range: TextRange,
    /// Its name.
    pub selection_range: TextRange,
    pub children: Vec<Symbol>,
}

fn symbol(node: &SyntaxNode, name: Option<ast::Name>, kind: SymbolKind, detail: Option<String>) -> Option<Symbol> {
    let name = name?;
    Some(Symbol {
        name: name.text(),
        detail,
        kind,
        range: node.text_range(),
        selection_range: name.syntax().text_range(),
        children: Vec::new(),
    })
}

/// The hierarchical outline of a file. Stops (unwinds with `Cancelled`) at the next declaration
/// once a newer change is waiting: a file of megabytes has hundreds of thousands.
pub fn document_symbols(db: &dyn Db, file: SourceFile) -> Vec<Symbol> {
    outline(&parse(db, file).source_file(), &|| db.unwind_if_revision_cancelled())
}

/// The outline of a parsed file; `checkpoint` runs before each declaration.
fn outline(file: &ast::SourceFile, checkpoint: &dyn Fn()) -> Vec<Symbol> {
    file.diagrams().filter_map(|d| diagram(&d, checkpoint)).collect()
}

fn diagram(diagram: &ast::Diagram, checkpoint: &dyn Fn()) -> Option<Symbol> {
    let kind_text = match diagram {
        ast::Diagram::ClassDiagram(_) => "ClassDiagram",
        ast::Diagram::ActivityDiagram(_) => "ActivityDiagram",
        ast::Diagram::ComponentDiagram(_) => "ComponentDiagram",
        ast::Diagram::ComponentInstanceDiagram(_) => "ComponentInstanceDiagram",
    };
    let mut sym = symbol(diagram.syntax(), diagram.name(), SymbolKind::Diagram, Some(kind_text.to_string()))?;
    for nested in ast::support::children::<ast::Diagram>(diagram.syntax()) {
        sym.children.extend(self::diagram(&nested, checkpoint));
    }
    match diagram {
        ast::Diagram::ClassDiagram(d) => sym.children.extend(d.type_decls().filter_map(|t| {
            checkpoint();
            type_decl(&t)
        })),
        ast::Diagram::ActivityDiagram(d) => {
            sym.children.extend(d.variables().filter_map(|v| symbol(v.syntax(), v.name(), SymbolKind::Variable, None)));
            for lane in d.swimlanes() {
                let owner = lane.owner().map(|o| format!("owner {}", o.text()));
                if let Some(mut lane_sym) = symbol(lane.syntax(), lane.name(), SymbolKind::Swimlane, owner) {
                    lane_sym.children.extend(lane.nodes().filter_map(|n| {
                        checkpoint();
                        node(&n)
                    }));
                    sym.children.push(lane_sym);
                }
            }
            sym.children.extend(d.nodes().filter_map(|n| {
                checkpoint();
                node(&n)
            }));
        }
        ast::Diagram::ComponentDiagram(d) => sym.children.extend(d.components().filter_map(|c| {
            checkpoint();
            component(&c)
        })),
        ast::Diagram::ComponentInstanceDiagram(d) => {
            for instance in d.instances() {
                checkpoint();
                let detail = instance.component().map(|c| c.text());
                if let Some(mut inst) = symbol(instance.syntax(), instance.name(), SymbolKind::Instance, detail) {
                    inst.children.extend(
                        instance.port_instances().filter_map(|p| symbol(p.syntax(), p.name(), SymbolKind::Port, None)),
                    );
                    sym.children.push(inst);
                }
            }
        }
    }
    Some(sym)
}

fn type_decl(decl: &ast::TypeDecl) -> Option<Symbol> {
    let (kind, detail) = match decl {
        ast::TypeDecl::Class(c) => (SymbolKind::Class, format!("{:?}", c.kind()).to_lowercase()),
        ast::TypeDecl::Interface(i) => (SymbolKind::Interface, format!("{:?} interface", i.role()).to_lowercase()),
        ast::TypeDecl::Enum(_) => (SymbolKind::Enum, "enum".to_string()),
        ast::TypeDecl::AttributeDef(_) => (SymbolKind::Attribute, "attribute".to_string()),
    };
    let mut sym = symbol(decl.syntax(), decl.name(), kind, Some(detail))?;
    if let ast::TypeDecl::Enum(e) = decl {
        sym.children.extend(e.values().filter_map(|v| symbol(v.syntax(), v.name(), SymbolKind::EnumValue, None)));
    }
    for member in decl.members() {
        let entry = match &member {
            ast::Member::Field(f) => {
                symbol(f.syntax(), f.name(), SymbolKind::Field, f.type_ref().map(|t| t.syntax().text().to_string()))
            }
            ast::Member::Association(a) => {
                symbol(a.syntax(), a.name(), SymbolKind::Field, a.target().map(|t| t.syntax().text().to_string()))
            }
            ast::Member::Method(m) => symbol(
                m.syntax(),
                m.name(),
                SymbolKind::Method,
                m.param_list().map(|p| collapse_whitespace(&p.syntax().text().to_string())),
            ),
        };
        sym.children.extend(entry);
    }
    Some(sym)
}

/// A node, with the nodes it holds (Sec. 9.2.2.3) as its children.
fn node(node: &ast::ActivityNode) -> Option<Symbol> {
    let detail = format!("{:?}", node.kind()).to_lowercase();
    let mut sym = symbol(node.syntax(), node.name(), SymbolKind::Node, Some(detail))?;
    sym.children.extend(node.nested_nodes().filter_map(|n| self::node(&n)));
    Some(sym)
}

fn component(component: &ast::Component) -> Option<Symbol> {
    let class = component.class()?;
    let mut sym = Symbol {
        name: class.text(),
        detail: Some(format!("{:?}", component.kind()).to_lowercase()),
        kind: SymbolKind::Component,
        range: component.syntax().text_range(),
        selection_range: class.syntax().text_range(),
        children: Vec::new(),
    };
    sym.children.extend(component.ports().filter_map(|p| symbol(p.syntax(), p.name(), SymbolKind::Port, None)));
    sym.children.extend(component.components().filter_map(|c| self::component(&c)));
    Some(sym)
}

/// `(int a,\n   int b)` → `(int a, int b)`.
pub(crate) fn collapse_whitespace(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn print(symbols: &[Symbol], depth: usize, out: &mut String) {
        for s in symbols {
            out.push_str(&format!(
                "{}{:?} {} {}\n",
                "  ".repeat(depth),
                s.kind,
                s.name,
                s.detail.clone().unwrap_or_default()
            ));
            print(&s.children, depth + 1, out);
        }
    }

    #[test]
    fn hierarchical_outline() {
        let parse = crate::parse(
            "ClassDiagram D { public class C { public int x; public void m(int a,\n int b); } public enum E { A } }
             ActivityDiagram Ad() { public int v; swimlane L, owner D.C { start S { => f; } final f; } }
             ComponentDiagram Cd { source D.C { port P ( provider p : I ); } }
             ComponentInstanceDiagram Cid { C1 instantiates D.C ( ) { PI : P ( provider p = I() ); } }",
        );
        let mut out = String::new();
        print(&outline(&parse.source_file(), &|| ()), 0, &mut out);
        assert_eq!(
            out,
            "Diagram D ClassDiagram\n  Class C class\n    Field x int\n    Method m (int a, int b)\n  Enum E enum\n    EnumValue A \n\
             Diagram Ad ActivityDiagram\n  Variable v \n  Swimlane L owner D.C\n    Node S start\n    Node f final\n\
             Diagram Cd ComponentDiagram\n  Component D.C source\n    Port P \n\
             Diagram Cid ComponentInstanceDiagram\n  Instance C1 D.C\n    Port PI \n"
        );
    }
}
