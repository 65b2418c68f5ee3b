//! A pipeline stage's parameter set as an edit of the model's text — `name = value` of the
//! instance replaced, or written into its argument list — so a value from elsewhere (`gudsl run
//! --set`, a control in the editor) is checked by the same rules as one typed (E0403) and the
//! text stays the one truth. A value must be one expression where it is written: one that would
//! change anything else of the text is refused.

use crate::{
    ast::{self, AstNode, HasName},
    db::{Db, SourceFile, Workspace},
    hir::{
        pipeline::{pipeline_plan, PipelinePlan},
        DefKind, Fqn, Semantics,
    },
    syntax::{TextRange, TextSize},
};

/// The edit that sets a parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParameterEdit {
    pub file: SourceFile,
    /// What is replaced and the text that replaces it.
    pub range: TextRange,
    pub text: String,
    /// Where the value stands in the text once edited (the range a problem with it is told at).
    pub value: TextRange,
}

/// The edit that sets `parameter` of the instance `instance` of the component-instance diagram
/// `diagram` (fully qualified) to `value`, as written in the model (`7`, `0.5`, `true`,
/// `"calibration.npy"`, `Scene.Sphere`); why there is none, naming what there is.
pub fn parameter_edit(
    db: &dyn Db,
    workspace: Workspace,
    diagram: &str,
    instance: &str,
    parameter: &str,
    value: &str,
) -> Result<ParameterEdit, String> {
    let plan = pipeline_plan(db, workspace, Fqn::new(db, diagram.to_string()))
        .as_ref()
        .ok_or_else(|| format!("no component-instance diagram `{diagram}`"))?;
    let class = known(plan, instance, parameter)?;
    let value = value.trim();
    if value.is_empty() {
        return Err(format!("`{instance}.{parameter}` needs a value"));
    }
    // Text as a shell leaves it (`calibration.npy`, its quotes gone) is text all the same.
    let quoted;
    let value = if is_text(db, workspace, class, parameter) && !value.starts_with('"') {
        quoted = format!("{value:?}");
        quoted.as_str()
    } else {
        value
    };
    let syntax = instance_syntax(db, workspace, plan, instance)?;
    let (range, text, value_at) = edit_of(&syntax, parameter, value);
    let file = plan.file;
    let edited = crate::text::with_edits(file.text(db), [(range, text.as_str())]);
    let value_range = TextRange::at(range.start() + value_at, TextSize::of(value));
    let errors_before = crate::db::parse(db, file).errors().len();
    if !written_alone(&edited, errors_before, syntax.syntax().text_range().start(), parameter, value_range) {
        return Err(format!(
            "`{value}` is not one value for `{instance}.{parameter}`: write a number, `true`/`false`, text in double quotes or an enum member"
        ));
    }
    Ok(ParameterEdit { file, range, text, value: value_range })
}

/// The component class (fully qualified) of `instance`; refuses an instance the plan has no
/// stage for, or a parameter its component has not, naming those there are.
fn known<'p>(plan: &'p PipelinePlan, instance: &str, parameter: &str) -> Result<&'p str, String> {
    let Some(stage) = plan.stages.iter().find(|s| s.instance == instance) else {
        let names: Vec<&str> = plan.stages.iter().map(|s| s.instance.as_str()).collect();
        return Err(format!("`{}` has no instance `{instance}` (it has {})", plan.diagram, names.join(", ")));
    };
    if stage.params.iter().all(|p| p.name != parameter) {
        let names: Vec<&str> = stage.params.iter().map(|p| p.name.as_str()).collect();
        let has = if names.is_empty() { "none".to_string() } else { names.join(", ") };
        return Err(format!("`{instance}` ({}) has no parameter `{parameter}` (its parameters: {has})", stage.class));
    }
    Ok(&stage.class)
}

/// Whether the field `parameter` of `class` (or of a base) holds text.
fn is_text(db: &dyn Db, workspace: Workspace, class: &str, parameter: &str) -> bool {
    let sema = Semantics::new(db, workspace);
    let Some(class) = sema.definition(class) else { return false };
    let field = sema.type_and_bases(class).into_iter().find_map(|def| match &def.kind {
        DefKind::Type(ty) => ty.fields.iter().find(|f| f.name == parameter).cloned(),
        _ => None,
    });
    field.is_some_and(|f| f.ty.builtin.as_deref() == Some("string"))
}

/// The instance's syntax in the diagram's declaration.
fn instance_syntax(
    db: &dyn Db,
    workspace: Workspace,
    plan: &PipelinePlan,
    instance: &str,
) -> Result<ast::ComponentInstance, String> {
    let sema = Semantics::new(db, workspace);
    let def = sema.lookup(&plan.diagram).iter().find(|d| d.kind == DefKind::ComponentInstanceDiagram);
    def.and_then(|def| sema.declaration(def))
        .and_then(|(node, _)| ast::ComponentInstanceDiagram::cast(node))
        .and_then(|diagram| diagram.instances().find(|i| i.name().is_some_and(|n| n.text() == instance)))
        .ok_or_else(|| format!("`{instance}` is not found in the text of `{}`", plan.diagram))
}

/// The edit writing `value` for `parameter` into `instance`, and where the value starts in the
/// edit's text: over the value written, else after the last argument, else into `( )`, else
/// as a new argument list after the component's name.
fn edit_of(instance: &ast::ComponentInstance, parameter: &str, value: &str) -> (TextRange, String, TextSize) {
    let list = instance.named_arg_list();
    let args: Vec<ast::NamedArg> = list.iter().flat_map(|l| l.args()).collect();
    let written = args.iter().find(|a| a.name().is_some_and(|n| n.text() == parameter));
    if let Some(old) = written.and_then(|a| a.value()) {
        return (old.syntax().text_range(), value.to_string(), TextSize::from(0));
    }
    let new = format!("{parameter} = {value}");
    let start = TextSize::of(parameter) + TextSize::of(" = ");
    match (args.last(), list.as_ref().and_then(|l| l.r_paren_token())) {
        (Some(last), _) => {
            (TextRange::empty(last.syntax().text_range().end()), format!(", {new}"), start + TextSize::of(", "))
        }
        (None, Some(close)) => {
            let open = list
                .as_ref()
                .and_then(|l| l.l_paren_token())
                .map_or(close.text_range().start(), |t| t.text_range().end());
            (TextRange::new(open, close.text_range().start()), new, start)
        }
        (None, None) => {
            let after = instance
                .component()
                .map_or_else(|| instance.syntax().text_range().end(), |c| c.syntax().text_range().end());
            (TextRange::empty(after), format!(" ({new})"), start + TextSize::of(" ("))
        }
    }
}

/// Whether, in the edited text, the instance at `start` writes `parameter` once, with exactly
/// `value` as its value, and the file parses as well as before (`errors_before`).
fn written_alone(edited: &str, errors_before: usize, start: TextSize, parameter: &str, value: TextRange) -> bool {
    let parse = crate::syntax::parse(edited);
    if parse.errors().len() > errors_before {
        return false;
    }
    let root = parse.syntax_node();
    let Some(instance) =
        root.descendants().filter_map(ast::ComponentInstance::cast).find(|i| i.syntax().text_range().start() == start)
    else {
        return false;
    };
    let values: Vec<TextRange> = instance
        .field_values()
        .filter(|a| a.name().is_some_and(|n| n.text() == parameter))
        .filter_map(|a| Some(a.value()?.syntax().text_range()))
        .collect();
    values == [value]
}
