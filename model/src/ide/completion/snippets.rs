//! The keyword snippets of each declaration level: diagrams at the top, classes and
//! interfaces in a class diagram, nodes in an activity diagram or swimlane, components and
//! instances, and qualifiers and types in a member list.

use crate::syntax::{NodeKind, SyntaxKind::*};

use super::{context::Ctx, finish, item, names::with_types, snippet, CompletionKind, Completions};

/// The snippets of the declaration level around the cursor.
pub(super) fn at_level(ctx: &Ctx) -> Completions {
    let (sema, at, typed) = (&ctx.sema, &ctx.at, ctx.typed.as_str());
    let mut items = Vec::new();
    // Declaration levels: keyword snippets.
    let level = at.ancestors().find(|a| {
        matches!(
            a.kind(),
            CLASS_DIAGRAM | ACTIVITY_DIAGRAM | SWIMLANE | COMPONENT_DIAGRAM | COMPONENT_INSTANCE_DIAGRAM | MEMBER_LIST
        )
    });
    match level.as_ref().map(|l| l.kind()) {
        Some(CLASS_DIAGRAM) => {
            items.push(snippet("class", "public class ${1:Name}\n{\n\t$0\n}", "class declaration"));
            items.push(snippet("interface", "public interface ${1:Name}\n{\n\t$0\n}", "interface declaration"));
            items.push(snippet("provider interface", "public interface provider ${1:Name}\n{\n\tpublic void provide${2:Data}(${3});\n}", "output interface of a component"));
            items.push(snippet("processor interface", "public interface processor ${1:Name}\n{\n\tpublic void process${2:Data}(${3});\n}", "input interface of a component"));
            items.push(snippet("enum", "public enum ${1:Name} { ${2:A}, ${3:B} }", "enumeration"));
            items.push(snippet("attribute", "public attribute ${1:Name}\n{\n\tpublic ${2:string} ${3:value};\n}", "generator attribute"));
            for kind in ["source", "filter", "sink"] {
                items.push(snippet(kind, &format!("public {kind} ${{1:Name}}\n{{\n\tpublic bool process(ConstIObjectParametersPtr parameters);\n}}"), "component class"));
            }
            items.push(item("import", CompletionKind::Keyword, None));
        }
        Some(ACTIVITY_DIAGRAM) | Some(SWIMLANE) => {
            if level.as_ref().is_some_and(|l| l.kind() == ACTIVITY_DIAGRAM) {
                items.push(snippet("swimlane", "swimlane ${1:Lane}, owner ${2:Class}\n{\n\tstart S\n\t{\n\t\t=> ${3:first};\n\t}\n\t$0\n\tfinal done;\n}", "swimlane with start and final nodes"));
            }
            for kind in NodeKind::ALL {
                items.push(snippet(kind.keyword(), node_snippet(kind), &format!("{} node", kind.keyword())));
            }
        }
        Some(MEMBER_LIST) => {
            for keyword in ["public", "protected", "private", "const", "ref", "global", "self"] {
                items.push(item(keyword, CompletionKind::Keyword, None));
            }
            return with_types(sema, at, typed, items);
        }
        Some(COMPONENT_DIAGRAM) => {
            for kind in ["source", "filter", "sink", "class"] {
                items.push(snippet(kind, &format!("{kind} ${{1:Class}}\n{{\n\tport ${{2:Port}} ( provider ${{3:out}} : ${{4:Interface}} );\n}}"), "component"));
            }
        }
        Some(COMPONENT_INSTANCE_DIAGRAM) => {
            items.push(snippet("instantiates", "${1:Name} instantiates ${2:Component} ( )\n{\n\t$0\n}", "component instance"));
        }
        _ => {
            for (kind, body) in [
                ("ClassDiagram", "ClassDiagram ${1:Name}\n{\n\t$0\n}"),
                ("ActivityDiagram", "ActivityDiagram ${1:Name}(${2})\n{\n\tswimlane ${3:Lane}\n\t{\n\t\tstart S\n\t\t{\n\t\t\t=> done;\n\t\t}\n\t\t$0\n\t\tfinal done;\n\t}\n}"),
                ("ComponentDiagram", "ComponentDiagram ${1:Name}\n{\n\t$0\n}"),
                ("ComponentInstanceDiagram", "ComponentInstanceDiagram ${1:Name}\n{\n\t$0\n}"),
            ] {
                items.push(snippet(kind, body, "diagram"));
            }
        }
    }
    finish(items)
}

/// The snippet of a node of `kind`, in LSP snippet syntax.
fn node_snippet(kind: NodeKind) -> &'static str {
    match kind {
        NodeKind::Start => "start ${1:S}\n{\n\t=> ${2:first};\n}",
        NodeKind::Action => "action ${1:name}(${2})\n{\n\t$0\n\t=> ${3:next};\n}",
        NodeKind::Decision => "decision ${1:name}\n{\n\t[${2:condition}] => ${3:yes};\n\t[] => ${4:no};\n}",
        NodeKind::Calc => "calc ${1:name}(${2})\n{\n\tcall ${3:Class}::${4:kernel}($5);\n\t=> ${6:next};\n}",
        NodeKind::CalcRange => "calcRange ${1:name}(${2})\n{\n\tcall ${3:Class}::${4:kernel}($5);\n\t=> ${6:next};\n}",
        NodeKind::Loop => "loop ${1:name}(var int ${2:i} = 0; $2 < ${3:n}; $2 = $2 + 1)\n{\n\t$0\n\t=> ${4:next};\n}",
        NodeKind::LoopWindow => "loopWindow ${1:name}(var int u = -${2:r}, var int v = -$2; u <= $2, v <= $2; u = u + 1, v = v + 1)\n{\n\t$0\n\t=> ${3:next};\n}",
        NodeKind::Fork => "fork ${1:name}\n{\n\t=> ${2:a};\n\t=> ${3:b};\n}",
        NodeKind::Join => "join ${1:name}\n{\n\t=> ${2:next};\n}",
        NodeKind::Final => "final ${1:done};",
    }
}
