//! Tests of the typed AST: the accessors find the right parts of real documents.

use super::*;
use crate::syntax::SyntaxKind;

fn file(text: &str) -> SourceFile {
    let parse = crate::parse(text);
    assert!(parse.errors().is_empty(), "{:?}", parse.errors());
    parse.source_file()
}

#[test]
fn class_diagram_accessors() {
    let source = file(
        "ClassDiagram Defs {
            import Other.*;
            [Attributes.GeneratorVisibility(visible = false), CppType(name = \"QImage\")]
            public abstract class Image<T> extends Base implements IImage, IOther {
                public global const ref int k = ref g;
                self aggregation [0 .. *] subImages : Image;
                self [1] contains : Pixel [0 .. *];
                public bool load(string filename, out ref int size) { return true; }
            }
            public interface provider IImageProvider { public void provideImage(ref Image image); }
            public filter MeanFilter implements IImageProvider { }
            public enum Mode { Fast, Slow = 2 }
            public attribute CppType { public string name; }
        }",
    );
    let Diagram::ClassDiagram(diagram) = source.diagrams().next().unwrap() else { panic!() };
    assert_eq!(diagram.name().unwrap().text(), "Defs");
    assert!(
        matches!(diagram.imports().next().unwrap().target(), Some(ImportTarget::Wildcard(p)) if p.text() == "Other")
    );
    let decls: Vec<TypeDecl> = diagram.type_decls().collect();
    assert_eq!(decls.len(), 5);

    let TypeDecl::Class(image) = &decls[0] else { panic!() };
    assert!(image.is_abstract());
    assert_eq!(image.kind(), ClassKind::Class);
    assert_eq!(image.template_params().map(|t| t.name().unwrap().text()).collect::<Vec<_>>(), ["T"]);
    assert_eq!(image.extends().map(|t| t.path().unwrap().text()).collect::<Vec<_>>(), ["Base"]);
    assert_eq!(image.implements().count(), 2);
    let attrs: Vec<String> = image.attribute_lists()[0].uses().map(|u| u.path().unwrap().text()).collect();
    assert_eq!(attrs, ["Attributes.GeneratorVisibility", "CppType"]);
    let members: Vec<Member> = image.members().collect();
    let Member::Field(k) = &members[0] else { panic!() };
    assert!(k.has_modifier(SyntaxKind::GLOBAL_KW) && k.has_modifier(SyntaxKind::CONST_KW));
    assert_eq!(k.modifiers().unwrap().visibility(), Some(Visibility::Public));
    let Member::Association(sub) = &members[1] else { panic!() };
    assert_eq!(sub.kind(), AssociationKind::Aggregation);
    assert_eq!(sub.own_multiplicity().unwrap().bounds(), (Some("0".into()), Some("*".into())));
    let Member::Association(contains) = &members[2] else { panic!() };
    assert_eq!(contains.own_multiplicity().unwrap().bounds(), (Some("1".into()), None));
    assert_eq!(contains.target_multiplicity().unwrap().bounds(), (Some("0".into()), Some("*".into())));
    let Member::Method(load) = &members[3] else { panic!() };
    assert_eq!(load.params().map(|p| p.name().unwrap().text()).collect::<Vec<_>>(), ["filename", "size"]);
    assert!(load.params().nth(1).unwrap().has_modifier(SyntaxKind::OUT_KW));
    assert_eq!(load.body().unwrap().statements().count(), 1);

    let TypeDecl::Interface(provider) = &decls[1] else { panic!() };
    assert_eq!(provider.role(), InterfaceRole::Provider);
    let TypeDecl::Class(mean) = &decls[2] else { panic!() };
    assert_eq!(mean.kind(), ClassKind::Filter);
    let TypeDecl::Enum(mode) = &decls[3] else { panic!() };
    assert_eq!(mode.values().map(|v| v.name().unwrap().text()).collect::<Vec<_>>(), ["Fast", "Slow"]);
    assert!(matches!(decls[4], TypeDecl::AttributeDef(_)));
}

#[test]
fn activity_diagram_accessors() {
    let source = file(
        "ActivityDiagram Main(int a, out int b), owner Defs.Image {
            public int gidx;
            var int local = 0;
            swimlane P1, owner Filtering.MeanFilter {
                start S1 { => init(a); }
                action init(int x) { gidx = x; [gidx > 0] => kernel; [] => f; }
                loopWindow kernel(var int u = -1, var int v = -1; u < 1, v < 1; u = u + 1, v = v + 1) { => f; }
                final f return gidx;
            }
        }",
    );
    let Diagram::ActivityDiagram(ad) = source.diagrams().next().unwrap() else { panic!() };
    assert_eq!(ad.params().count(), 2);
    assert_eq!(ad.owner().unwrap().text(), "Defs.Image");
    assert_eq!(ad.variables().count(), 1);
    assert_eq!(ad.var_decls().count(), 1);
    let lane = ad.swimlanes().next().unwrap();
    assert_eq!(lane.owner().unwrap().text(), "Filtering.MeanFilter");
    let nodes: Vec<ActivityNode> = lane.nodes().collect();
    assert_eq!(
        nodes.iter().map(|n| n.kind()).collect::<Vec<_>>(),
        [NodeKind::Start, NodeKind::Action, NodeKind::LoopWindow, NodeKind::Final]
    );
    let start_transition = nodes[0].transitions().next().unwrap();
    assert_eq!(start_transition.target().unwrap().text(), "init");
    assert_eq!(start_transition.args().count(), 1);
    let init: Vec<Transition> = nodes[1].transitions().collect();
    assert!(init[0].guard().unwrap().condition().is_some());
    assert!(init[1].guard().unwrap().condition().is_none(), "empty guard");
    assert_eq!(nodes[1].statements().count(), 1);
    let header = nodes[2].loop_header().unwrap();
    assert_eq!(header.sections().map(|s| s.parts().count()).collect::<Vec<_>>(), [2, 2, 2]);
    assert!(nodes[3].return_value().is_some());
}

#[test]
fn component_diagram_accessors() {
    let source = file(
        "ComponentDiagram Components {
            source Defs.Camera {
                async buffered port Out ( provider Image : Defs.IImageProvider, processor Ctl : Defs.IControl );
                [CameraToFilter source Out.Image ==> target In.Image]
            }
        }
        ComponentInstanceDiagram Instances {
            Camera1 instantiates Defs.Camera (width = 640, height = 480) {
                OutPort : Out ( provider Image = IImageProvider() );
                [ source OutPort.Image ==> target Viewer1.InPort.Image ]
            }
        }",
    );
    let mut diagrams = source.diagrams();
    let Some(Diagram::ComponentDiagram(cd)) = diagrams.next() else { panic!() };
    let camera = cd.components().next().unwrap();
    assert_eq!(camera.kind(), ClassKind::Source);
    assert_eq!(camera.class().unwrap().text(), "Defs.Camera");
    let port = camera.ports().next().unwrap();
    assert!(port.is_async() && port.is_buffered());
    let roles: Vec<_> = port.connectors().map(|c| c.role().unwrap()).collect();
    assert_eq!(roles, [ConnectorRole::Provider, ConnectorRole::Processor]);
    let connection = camera.connections().next().unwrap();
    assert_eq!(connection.connection_name().unwrap().text(), "CameraToFilter");
    assert_eq!(connection.source().unwrap().text(), "Out.Image");
    assert_eq!(connection.target().unwrap().text(), "In.Image");

    let Some(Diagram::ComponentInstanceDiagram(cid)) = diagrams.next() else { panic!() };
    let camera1 = cid.instances().next().unwrap();
    assert_eq!(camera1.component().unwrap().text(), "Defs.Camera");
    assert_eq!(camera1.field_values().map(|f| f.name().unwrap().text()).collect::<Vec<_>>(), ["width", "height"]);
    let port = camera1.port_instances().next().unwrap();
    assert_eq!(port.port().unwrap().text(), "Out");
    assert_eq!(port.connectors().next().unwrap().interface().unwrap().text(), "IImageProvider");
    let binding = camera1.bindings().next().unwrap();
    assert!(binding.connection_name().is_none());
    assert_eq!(binding.target().unwrap().text(), "Viewer1.InPort.Image");
}

#[test]
fn expressions_keep_precedence() {
    let source = file("ClassDiagram D { class C { void m() { x = a + b * c == d && !e; } } }");
    let Some(Diagram::ClassDiagram(d)) = source.diagrams().next() else { panic!() };
    let Some(TypeDecl::Class(c)) = d.type_decls().next() else { panic!() };
    let Some(Member::Method(m)) = c.members().next() else { panic!() };
    let Some(Stmt::ExprStmt(stmt)) = m.body().unwrap().statements().next() else { panic!() };
    let Some(Expr::BinExpr(assign)) = stmt.expr() else { panic!() };
    assert!(assign.is_assignment());
    let Some(Expr::BinExpr(and)) = assign.rhs() else { panic!() };
    assert_eq!(and.op().unwrap().kind(), SyntaxKind::AMP2);
    let Some(Expr::BinExpr(eq)) = and.lhs() else { panic!() };
    assert_eq!(eq.op().unwrap().kind(), SyntaxKind::EQ2);
    let Some(Expr::BinExpr(plus)) = eq.lhs() else { panic!() };
    assert_eq!(plus.op().unwrap().kind(), SyntaxKind::PLUS);
    assert!(matches!(plus.rhs(), Some(Expr::BinExpr(_))));
    assert!(matches!(and.rhs(), Some(Expr::PrefixExpr(_))));
}
