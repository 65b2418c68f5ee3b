//! Objects (Sec. 9.1.1, "as in C# and Java"): the methods of a type differ in their parameter
//! types, and an override returns what the method it overrides returns (or a subtype of it).

use std::collections::HashMap;

use super::{Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasName},
    hir::{
        components::signature_key,
        definitions::{DefKind, Definition},
        diagnostics::Related,
        items::{type_signature, TypeSignature},
        ty::Ty,
    },
    syntax::TextRange,
};

/// The methods `decl` (declared as `fqn`) declares: no two of one name and parameter types, and
/// no override of another return type.
pub(super) fn methods(ctx: &mut Ctx, scope: &Scope, fqn: &str, decl: &ast::TypeDecl) {
    let Some(def) = ctx.sema.definition(fqn) else { return };
    // Types are compared as spelled first (`signature_key`: simple names), which costs no
    // resolution: two spellings of one type have one simple name, so methods whose spelled
    // signatures differ differ. Only equal spellings are resolved and compared.
    let spelled = |name: &str, params: Vec<TypeSignature>| signature_key(name, &params);
    let methods: Vec<(ast::Method, ast::Name, String)> = decl
        .members()
        .filter_map(|m| match m {
            ast::Member::Method(method) => {
                let name = method.name()?;
                let key = spelled(&name.text(), method.params().map(|p| type_signature(p.type_ref())).collect());
                Some((method, name, key))
            }
            _ => None,
        })
        .collect();
    let mut spellings: HashMap<&str, usize> = HashMap::new();
    for (_, _, key) in &methods {
        *spellings.entry(key).or_default() += 1;
    }
    let ancestors = ctx.sema.type_and_bases(def).into_iter().filter(|d| d.fqn != def.fqn);
    let inherited: std::collections::HashSet<String> = ancestors
        .filter_map(|d| match &d.kind {
            DefKind::Type(item) => {
                Some(item.methods.iter().map(|m| spelled(&m.name, m.params.iter().map(|p| p.ty.clone()).collect())))
            }
            _ => None,
        })
        .flatten()
        .collect();
    let mut declared: HashMap<(String, Vec<TypeSignature>), TextRange> = HashMap::new();
    for (method, name, key) in &methods {
        let (twice, overrides) = (spellings[key.as_str()] > 1, inherited.contains(key));
        if !twice && !overrides {
            continue;
        }
        let params: Vec<TypeSignature> =
            method.params().map(|p| resolved(ctx, scope, &type_signature(p.type_ref()))).collect();
        let range = name.syntax().text_range();
        match declared.get(&(name.text(), params.clone())) {
            Some(&first) => ctx.sink.error_with_related(
                DiagnosticCode::DuplicateName,
                range,
                format!("method `{}({})` is declared twice with these parameter types", name.text(), describe(&params)),
                vec![Related { file: ctx.file, range: first, message: "first declared here".to_string() }],
            ),
            None => drop(declared.insert((name.text(), params.clone()), range)),
        }
        if overrides {
            override_return(ctx, scope, def, method, &params);
        }
    }
}

/// A method of a base with the same name and parameter types returns what `method` returns, or
/// a supertype of it (covariant returns, as C# 9, Java and C++ allow for classes).
fn override_return(ctx: &mut Ctx, scope: &Scope, def: &Definition, method: &ast::Method, params: &[TypeSignature]) {
    let Some(name) = method.name().map(|n| n.text()) else { return };
    let returns = ctx.sema.ty(&type_signature(method.return_type()), scope);
    for base in ctx.sema.bases(def) {
        for (owner, overridden) in ctx.sema.methods(base, &name) {
            let owner_scope = Scope::of(owner);
            let same_params = overridden.params.len() == params.len()
                && overridden.params.iter().zip(params).all(|(p, q)| resolved(ctx, &owner_scope, &p.ty) == *q);
            if !same_params {
                continue;
            }
            let base_returns = ctx.sema.ty(&overridden.ret, &owner_scope);
            let covariant = match (&returns, &base_returns) {
                (Ty::Named(sub), Ty::Named(sup)) => ctx.sema.is_subtype(sub, sup),
                (Ty::Unknown, _) | (_, Ty::Unknown) => true,
                (a, b) => a == b,
            };
            if !covariant {
                let range =
                    method.return_type().map_or_else(|| method.syntax().text_range(), |t| t.syntax().text_range());
                ctx.sink.error(
                    DiagnosticCode::OverrideReturnType,
                    range,
                    format!(
                        "`{name}` overrides `{}::{name}`, which returns `{base_returns}`: an override returns the same type (or a subclass of it), here `{returns}`",
                        owner.fqn
                    ),
                );
                return;
            }
        }
    }
}

/// A written type with its named types fully qualified, so that two spellings of one type
/// compare equal (built-in names such as `float4` are left as written: they name no type).
fn resolved(ctx: &Ctx, scope: &Scope, ty: &TypeSignature) -> TypeSignature {
    let mut ty = ty.clone();
    let mut denoted = ctx.sema.ty(&ty, scope);
    while let Ty::Array(inner) | Ty::Ref { inner, .. } = denoted {
        denoted = *inner;
    }
    if let Ty::Named(fqn) = denoted {
        ty.path = Some(fqn);
    }
    ty.args = ty.args.iter().map(|arg| resolved(ctx, scope, arg)).collect();
    // `global` is where a kernel's buffer lives, not another parameter type.
    ty.is_global = false;
    ty
}

/// Parameter types as written, after resolution: `ref unsigned int, Pkg.Image[]`.
fn describe(params: &[TypeSignature]) -> String {
    let describe_one = |p: &TypeSignature| {
        let name = p.builtin.clone().or_else(|| p.path.clone()).unwrap_or_default();
        let (reference, unsigned) = (if p.is_ref { "ref " } else { "" }, if p.is_unsigned { "unsigned " } else { "" });
        format!("{reference}{unsigned}{name}{}", "[]".repeat(p.array_dims))
    };
    params.iter().map(describe_one).collect::<Vec<_>>().join(", ")
}
