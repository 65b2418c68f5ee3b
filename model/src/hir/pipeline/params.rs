//! A stage's parameters: every field of its component class (inherited ones too), with the
//! value the instance writes or else the field's default, each a constant (numbers, text,
//! `true`/`false`, enum members, and arithmetic on numbers), checked against the field's
//! `ToF.Range`/`ToF.Odd` attributes; fields marked `ToF.InputFile` name files to read (and need
//! a value). A field with neither has no value ([`Value::Missing`]: C++'s default).

use std::collections::HashMap;

use super::{Param, Value};
use crate::{
    ast::{self, AstNode, HasModifiers},
    hir::{
        definitions::{DefKind, Definition},
        diagnostics::{DiagnosticCode, Diagnostics},
        items::{TypeKind, TypeSignature},
        scope::Scope,
        semantics::Semantics,
        ty::{self, Ty},
    },
    syntax::{SyntaxKind, TextRange},
};

/// The attributes that constrain a parameter, by fully qualified name.
const RANGE: &str = "ToF.Range";
const ODD: &str = "ToF.Odd";
const INPUT_FILE: &str = "ToF.InputFile";

/// The parameters of an instance of `class`: its fields (the class's own first, then its
/// bases'), valued as `written` says or by their defaults; problems go to `sink`, at the value
/// written or, for a default or a missing value, at `instance_range`.
pub(super) fn parameters(
    sema: &Semantics,
    class: &Definition,
    written: &HashMap<String, (ast::Expr, Scope)>,
    instance_range: TextRange,
    sink: &mut Diagnostics,
) -> Vec<Param> {
    let mut params: Vec<Param> = Vec::new();
    for def in sema.type_and_bases(class) {
        let DefKind::Type(ty) = &def.kind else { continue };
        if !matches!(ty.kind, TypeKind::Class(_)) {
            continue;
        }
        for field in &ty.fields {
            if params.iter().any(|p| p.name == field.name) {
                continue;
            }
            let Some(ast::Member::Field(decl)) = sema.member_declaration(def, &field.name) else { continue };
            let declared_scope = Scope::of(def);
            let (value, at) = match written.get(&field.name) {
                Some((expr, scope)) => (constant(sema, scope, expr), Some(expr.syntax().text_range())),
                None => (decl.initializer().and_then(|e| constant(sema, &declared_scope, &e)), None),
            };
            let range = at.unwrap_or(instance_range);
            let param = Param {
                name: field.name.clone(),
                value: value.clone().unwrap_or(Value::Missing),
                written: at,
                input_file: false,
                control: control_of(sema, &declared_scope, &field.ty),
            };
            let declared = Declared { scope: &declared_scope, decl: &decl, ty: &field.ty };
            params.push(check(sema, declared, param, range, value.is_none() && at.is_some(), sink));
        }
    }
    params
}

/// A parameter's field: where it is declared, its declaration and its type.
#[derive(Clone, Copy)]
struct Declared<'a> {
    scope: &'a Scope,
    decl: &'a ast::Field,
    ty: &'a TypeSignature,
}

/// The field's type and constraints on the parameter; a value that breaks one is an error at
/// `range`.
fn check(
    sema: &Semantics,
    Declared { scope, decl, ty }: Declared,
    mut param: Param,
    range: TextRange,
    not_constant: bool,
    sink: &mut Diagnostics,
) -> Param {
    let name = param.name.clone();
    if not_constant {
        sink.error(
            DiagnosticCode::ParameterValue,
            range,
            format!("`{name}` needs a constant: a number, text, `true`/`false` or an enum member"),
        );
        return param;
    }
    param.value = match converted(sema, scope, ty, param.value) {
        Ok(value) => value,
        Err((value, wanted)) => {
            sink.error(DiagnosticCode::ParameterValue, range, format!("`{name}` is {}, {wanted}", shown(&value)));
            param.value = value;
            return param;
        }
    };
    // One problem a value: a window of 2 is out of range, and saying it is even adds nothing.
    let mut reported = false;
    for attribute in decl.attribute_lists().iter().flat_map(|list| list.uses()) {
        let Some(def) = attribute.path().and_then(|p| sema.resolve(scope, &p.text())) else { continue };
        let args: HashMap<String, Value> = attribute
            .named_arg_list()
            .into_iter()
            .flat_map(|list| list.args())
            .filter_map(|arg| Some((arg.name()?.text(), constant(sema, scope, &arg.value()?)?)))
            .collect();
        match def.fqn.as_str() {
            INPUT_FILE => param.input_file = true,
            RANGE => {
                let (Some(min), Some(max)) =
                    (args.get("min").and_then(Value::number), args.get("max").and_then(Value::number))
                else {
                    continue;
                };
                param.control.range = Some((min.into(), max.into()));
                if let Some(value) = param.value.number() {
                    if value < min || value > max {
                        reported = true;
                        sink.error(
                            DiagnosticCode::ParameterValue,
                            range,
                            format!("`{name}` is {}, outside its range {} to {}", show(value), show(min), show(max)),
                        );
                    }
                }
            }
            ODD => {
                param.control.odd = true;
                if let Some(value) = param.value.number().filter(|_| !reported) {
                    if value.fract() != 0.0 || value.rem_euclid(2.0) != 1.0 {
                        sink.error(
                            DiagnosticCode::ParameterValue,
                            range,
                            format!("`{name}` is {}, but must be odd (a window centred on its pixel)", show(value)),
                        );
                    }
                }
            }
            _ => {}
        }
    }
    if param.value == Value::Missing && param.input_file {
        sink.error(DiagnosticCode::ParameterValue, range, format!("`{name}` names the file to read: give it a path"));
    }
    param
}

/// A field's type as a control offers it (its range and oddness are its attributes'): an
/// enum's members as a model writes them.
fn control_of(sema: &Semantics, scope: &Scope, ty: &TypeSignature) -> super::Control {
    let written = ty.builtin.clone().or_else(|| ty.path.clone()).unwrap_or_default();
    let def = ty.path.as_deref().and_then(|path| sema.resolve(scope, path));
    let choices = match def.as_ref().map(|d| &d.kind) {
        Some(DefKind::Type(item)) if item.kind == TypeKind::Enum => {
            let simple = written.rsplit('.').next().unwrap_or(&written);
            item.enum_values.iter().map(|member| format!("{simple}.{member}")).collect()
        }
        _ => Vec::new(),
    };
    super::Control { ty: written, range: None, odd: false, choices }
}

/// A number as a user writes it: `5`, `0.5`.
fn show(value: f64) -> String {
    format!("{value}")
}

/// A value as a user writes it.
fn shown(value: &Value) -> String {
    match value {
        Value::Int(v) => v.to_string(),
        Value::Float(v) => show(v.get()),
        Value::Bool(v) => v.to_string(),
        Value::Text(text) => format!("{text:?}"),
        Value::Enum(member) => member.clone(),
        Value::Missing => "missing".to_string(),
    }
}

/// `value` converted to the field's type as C converts a constant: a whole floating-point
/// number to an integer, a number to `bool` (non-zero: `true`) and back; why it cannot be where C would
/// change its value (`2.5` into an `int`, `-1` into an `unsigned`). A value of another kind
/// is left as it is: validation reports it (E0225).
fn converted(sema: &Semantics, scope: &Scope, ty: &TypeSignature, value: Value) -> Result<Value, (Value, String)> {
    let resolved = ty::from_signature(ty, &mut |path| sema.resolve(scope, path).map(|d| d.fqn.clone()));
    match (&resolved, value) {
        (Ty::Int | Ty::UInt, Value::Float(v)) if v.get().fract() == 0.0 && v.get().abs() < 9.0e15 => {
            converted(sema, scope, ty, Value::Int(v.get() as i64))
        }
        (Ty::Int | Ty::UInt, value @ Value::Float(_)) => Err((value, "but must be a whole number".to_string())),
        (Ty::UInt, value @ Value::Int(..0)) => {
            Err((value, "but must be at least 0 (the field is unsigned)".to_string()))
        }
        (Ty::Int | Ty::UInt | Ty::Float, Value::Bool(v)) => Ok(Value::Int(i64::from(v))),
        (Ty::Bool, Value::Int(v)) => Ok(Value::Bool(v != 0)),
        (Ty::Bool, Value::Float(v)) => Ok(Value::Bool(v.get() != 0.0)),
        (_, value) => Ok(value),
    }
}

/// The constant an expression denotes, or `None` if it is not one.
pub(super) fn constant(sema: &Semantics, scope: &Scope, expr: &ast::Expr) -> Option<Value> {
    match expr {
        ast::Expr::Literal(literal) => Some(match literal.value()? {
            ast::LiteralValue::Int { value, .. } => Value::Int(i64::try_from(value).ok()?),
            ast::LiteralValue::Float(value) => Value::Float(value.into()),
            ast::LiteralValue::Str(text) => Value::Text(text),
            ast::LiteralValue::Bool(value) => Value::Bool(value),
            ast::LiteralValue::Char(_) | ast::LiteralValue::Null => return None,
        }),
        ast::Expr::ParenExpr(inner) => constant(sema, scope, &inner.expr()?),
        ast::Expr::PrefixExpr(prefix) => {
            let value = constant(sema, scope, &prefix.operand()?)?;
            match (prefix.op()?.kind(), value) {
                (SyntaxKind::MINUS, Value::Int(v)) => Some(Value::Int(v.checked_neg()?)),
                (SyntaxKind::MINUS, Value::Float(v)) => Some(Value::Float((-v.get()).into())),
                (SyntaxKind::PLUS, value @ (Value::Int(_) | Value::Float(_))) => Some(value),
                (SyntaxKind::BANG, Value::Bool(v)) => Some(Value::Bool(!v)),
                _ => None,
            }
        }
        ast::Expr::BinExpr(bin) => {
            let (lhs, rhs) = (constant(sema, scope, &bin.lhs()?)?, constant(sema, scope, &bin.rhs()?)?);
            arithmetic(bin.op()?.kind(), lhs, rhs)
        }
        ast::Expr::MemberExpr(member) => {
            let name = member.member()?.text();
            let ty = path_text(&member.receiver()?)?;
            let def = sema.resolve(scope, &ty)?;
            match &def.kind {
                DefKind::Type(item) if item.kind == TypeKind::Enum && item.enum_values.contains(&name) => {
                    Some(Value::Enum(name))
                }
                _ => None,
            }
        }
        _ => None,
    }
}

/// `A.B` written as names and member accesses.
fn path_text(expr: &ast::Expr) -> Option<String> {
    match expr {
        ast::Expr::NameExpr(name) => Some(name.name_ref()?.text()),
        ast::Expr::MemberExpr(member) => {
            Some(format!("{}.{}", path_text(&member.receiver()?)?, member.member()?.text()))
        }
        _ => None,
    }
}

/// `+ - * /` on constant numbers: integers stay integers (division truncates, by zero is no
/// constant), a floating-point operand makes the result one.
fn arithmetic(op: SyntaxKind, lhs: Value, rhs: Value) -> Option<Value> {
    if let (Value::Int(a), Value::Int(b)) = (&lhs, &rhs) {
        return Some(Value::Int(match op {
            SyntaxKind::PLUS => a.checked_add(*b)?,
            SyntaxKind::MINUS => a.checked_sub(*b)?,
            SyntaxKind::STAR => a.checked_mul(*b)?,
            SyntaxKind::SLASH => a.checked_div(*b)?,
            _ => return None,
        }));
    }
    let (a, b) = (lhs.number()?, rhs.number()?);
    let value = match op {
        SyntaxKind::PLUS => a + b,
        SyntaxKind::MINUS => a - b,
        SyntaxKind::STAR => a * b,
        SyntaxKind::SLASH if b != 0.0 => a / b,
        _ => return None,
    };
    Some(Value::Float(value.into()))
}

/// The written values of an instance's fields (or a connector instance's), by name, with the
/// scope they are read in.
pub(super) fn written_values(
    args: impl Iterator<Item = ast::NamedArg>,
    scope: &Scope,
) -> HashMap<String, (ast::Expr, Scope)> {
    args.filter_map(|arg| Some((arg.name()?.text(), (arg.value()?, scope.clone())))).collect()
}

/// The `bufferSize` a connector instance gives, or its interface's default (4 without one).
pub(super) fn buffer_size(sema: &Semantics, scope: &Scope, connector: &ast::CidConnector) -> usize {
    let written = connector
        .field_values()
        .find(|arg| arg.name().is_some_and(|n| n.text() == "bufferSize"))
        .and_then(|arg| constant(sema, scope, &arg.value()?));
    let default = || {
        let interface = sema.resolve(scope, &connector.interface()?.text())?;
        let ast::Member::Field(field) = sema.member_declaration(interface, "bufferSize")? else { return None };
        constant(sema, &Scope::of(interface), &field.initializer()?)
    };
    written.or_else(default).and_then(|v| v.number()).filter(|n| *n >= 1.0).map_or(4, |n| n as usize)
}
