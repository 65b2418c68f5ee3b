//! OpenCL's atomic functions (`atomic_add`, `atomic_inc`, `atomic_min`, … of OpenCL C 1.1) as
//! WGSL's atomic built-ins. The pointer an atomic function takes is a buffer or `shared`
//! parameter, or one plus an offset (`counts + bin`); such a parameter's elements are
//! `atomic<i32>`/`atomic<u32>` in WGSL, so every other read of it is an `atomicLoad` and every
//! write an `atomicStore` (a plain `a[i] += v` stays the read-modify-write C does, not atomic).

use std::collections::HashSet;

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::{Definition, Scope, Semantics, Ty},
    syntax::{SyntaxKind, SyntaxNode},
};

use crate::{
    emitter::{bare, ident, Emitter, GENERATED},
    types::value_type,
    Binding,
};

/// The parameters whose elements an atomic function works on, among the calls under `root`.
pub(crate) fn atomic_targets(root: &SyntaxNode) -> HashSet<String> {
    root.descendants()
        .filter_map(ast::CallExpr::cast)
        .filter(|call| callee_name(call).is_some_and(|name| name.starts_with("atomic_")))
        .filter_map(|call| call.args().next())
        .filter_map(|pointer| pointer_parts(&pointer).map(|(name, _)| name))
        .collect()
}

/// The kernel memory parameters among `names` whose elements an atomic function works on: under
/// `root`, or in a method of `owner` or a diagram that a call under `root` hands them to, by
/// name, however deep (their elements are then `atomic<…>` in the whole module).
pub(crate) fn atomic_memory(
    sema: &Semantics<'_>,
    owner: Option<&Definition>,
    root: &SyntaxNode,
    names: &HashSet<String>,
) -> HashSet<String> {
    through_calls(sema, owner, root, names, &mut HashSet::new())
}

fn through_calls(
    sema: &Semantics<'_>,
    owner: Option<&Definition>,
    root: &SyntaxNode,
    names: &HashSet<String>,
    seen: &mut HashSet<(SyntaxNode, String)>,
) -> HashSet<String> {
    let mut out: HashSet<String> = atomic_targets(root).into_iter().filter(|n| names.contains(n)).collect();
    for (callee, params, args) in calls_under(sema, owner, root) {
        for (param, arg) in params.iter().zip(&args) {
            let Some(arg) = arg.as_ref().filter(|a| names.contains(*a) && !out.contains(*a)) else { continue };
            if !seen.insert((callee.clone(), param.clone())) {
                continue;
            }
            let param_only = HashSet::from([param.clone()]);
            if through_calls(sema, owner, &callee, &param_only, seen).contains(param) {
                out.insert(arg.clone());
            }
        }
    }
    out
}

/// The calls under `root` of methods of `owner` and of diagrams: each callee's declaration, its
/// parameters' names, and the name each argument is (if it is one).
fn calls_under(
    sema: &Semantics<'_>,
    owner: Option<&Definition>,
    root: &SyntaxNode,
) -> Vec<(SyntaxNode, Vec<String>, Vec<Option<String>>)> {
    let param_names = |params: &mut dyn Iterator<Item = ast::Param>| -> Vec<String> {
        params.map(|p| p.name().map(|n| n.text()).unwrap_or_default()).collect()
    };
    let arg_names = |args: &mut dyn Iterator<Item = ast::Expr>| -> Vec<Option<String>> {
        args.map(|a| match a {
            ast::Expr::NameExpr(name) => name.name_ref().map(|n| n.text()),
            _ => None,
        })
        .collect()
    };
    let mut out = Vec::new();
    for node in root.descendants() {
        if let Some(call) = ast::CallExpr::cast(node.clone()) {
            let (Some(owner), Some(name)) = (owner, callee_name(&call)) else { continue };
            if let [(_, method)] = &sema.method_declarations(owner, &name, call.args().count())[..] {
                out.push((method.syntax().clone(), param_names(&mut method.params()), arg_names(&mut call.args())));
            }
        } else if let Some(call) = ast::CallBehaviorExpr::cast(node) {
            let Some(path) = call.behavior() else { continue };
            let def = sema.resolve(&Scope::at(call.syntax()), &path.text());
            let diagram = def.and_then(|d| sema.declaration(d)).and_then(|(node, _)| ast::ActivityDiagram::cast(node));
            if let Some(diagram) = diagram {
                out.push((diagram.syntax().clone(), param_names(&mut diagram.params()), arg_names(&mut call.args())));
            }
        }
    }
    out
}

fn callee_name(call: &ast::CallExpr) -> Option<String> {
    match call.callee()? {
        ast::Expr::NameExpr(name) => Some(name.name_ref()?.text()),
        _ => None,
    }
}

/// `p`, `p + i`, `i + p` or `p - i`: the name `p` and the offset (negated for `-`).
fn pointer_parts(pointer: &ast::Expr) -> Option<(String, Option<(ast::Expr, bool)>)> {
    let name_of = |expr: &ast::Expr| match expr {
        ast::Expr::NameExpr(name) => name.name_ref().map(|n| n.text()),
        _ => None,
    };
    match pointer {
        ast::Expr::ParenExpr(inner) => pointer_parts(&inner.expr()?),
        ast::Expr::BinExpr(bin) => {
            let (lhs, rhs, op) = (bin.lhs()?, bin.rhs()?, bin.op()?.kind());
            match (name_of(&lhs), name_of(&rhs), op) {
                (Some(name), _, SyntaxKind::PLUS | SyntaxKind::MINUS) => {
                    Some((name, Some((rhs, op == SyntaxKind::MINUS))))
                }
                (None, Some(name), SyntaxKind::PLUS) => Some((name, Some((lhs, false)))),
                _ => None,
            }
        }
        other => Some((name_of(other)?, None)),
    }
}

impl Emitter<'_> {
    /// `atomic_add(p, v)` and the others: the atomic built-in on the element `p` points to,
    /// giving the old value.
    pub fn atomic(&mut self, call: &ast::CallExpr, name: &str, args: &[ast::Expr]) -> String {
        let Some(pointer) = args.first() else {
            return self.unsupported(call.syntax(), "an atomic function takes a pointer");
        };
        // A buffer a function is bound to is atomic only if `atomic_memory` followed it there:
        // the kernel declares its buffers.
        let bound = pointer_parts(pointer).map(|(name, _)| name).filter(|name| self.global_name(name) != *name);
        if let Some(name) = bound.filter(|name| !self.atomics.contains(&self.global_name(name))) {
            let message = format!(
                "`{name}` is the kernel's `{}`, but the generator could not follow it here from the kernel \
                 (a call of an overloaded method?): pass it by name through calls of one method each",
                self.global_name(&name)
            );
            return self.unsupported(pointer.syntax(), message);
        }
        let Some((element, ty)) = self.atomic_pointer(pointer) else {
            return self.unsupported(
                pointer.syntax(),
                "an atomic function works on an element of an `int` or `unsigned int` buffer or `shared` parameter \
                 (`p` or `p + i`)",
            );
        };
        let one = if ty == Ty::UInt { "1u" } else { "1i" };
        let operand = |emitter: &mut Self, i: usize| match args.get(i) {
            Some(arg) => bare(emitter.expr_as(arg, &ty)),
            None => emitter.unsupported(call.syntax(), format!("`{name}` takes {} arguments", i + 1)),
        };
        let (function, value) = match name {
            "atomic_add" => ("atomicAdd", operand(self, 1)),
            "atomic_sub" => ("atomicSub", operand(self, 1)),
            "atomic_xchg" => ("atomicExchange", operand(self, 1)),
            "atomic_min" => ("atomicMin", operand(self, 1)),
            "atomic_max" => ("atomicMax", operand(self, 1)),
            "atomic_and" => ("atomicAnd", operand(self, 1)),
            "atomic_or" => ("atomicOr", operand(self, 1)),
            "atomic_xor" => ("atomicXor", operand(self, 1)),
            "atomic_inc" => ("atomicAdd", one.to_string()),
            "atomic_dec" => ("atomicSub", one.to_string()),
            "atomic_cmpxchg" => {
                // WGSL's compare-exchange may fail spuriously; OpenCL's does not: a helper
                // retries (`compare_exchange_helpers`).
                let (compare, value) = (operand(self, 1), operand(self, 2));
                let Some((buffer, at)) = element.strip_suffix(']').and_then(|e| e.split_once('[')) else {
                    return self.unsupported(call.syntax(), "an incomplete pointer");
                };
                let helper = format!("{GENERATED}cmpxchg_{buffer}");
                self.compare_exchanged.insert((buffer.to_string(), value_type(&ty).unwrap_or_default()));
                return format!("{helper}({at}, {compare}, {value})");
            }
            _ => return self.unsupported(call.syntax(), format!("`{name}` has no WGSL form in the generator yet")),
        };
        format!("{function}(&{element}, {value})")
    }

    /// The helpers of `atomic_cmpxchg`, one per buffer it works on: OpenCL's strong
    /// compare-exchange from WGSL's weak one.
    pub fn compare_exchange_helpers(&self) -> String {
        let mut out = String::new();
        for (buffer, ty) in &self.compare_exchanged {
            out.push_str(&format!(
                "// atomic_cmpxchg on `{buffer}`: retried until it exchanges or finds another value\n\
                 fn {GENERATED}cmpxchg_{buffer}(at: i32, compare: {ty}, value: {ty}) -> {ty} {{\n    \
                 var result = atomicCompareExchangeWeak(&{buffer}[at], compare, value);\n    \
                 while !result.exchanged && result.old_value == compare {{\n        \
                 result = atomicCompareExchangeWeak(&{buffer}[at], compare, value);\n    \
                 }}\n    \
                 return result.old_value;\n}}\n\n"
            ));
        }
        out
    }

    /// The element an atomic function's pointer names, as WGSL (`counts[bin]`), and its type.
    fn atomic_pointer(&mut self, pointer: &ast::Expr) -> Option<(String, Ty)> {
        let (name, offset) = pointer_parts(pointer)?;
        if !matches!(self.binding(&name), Some(Binding::Storage { .. } | Binding::Workgroup { .. })) {
            return None;
        }
        let ty = match self.params.get(&name).map(|p| element_type(&p.ty)) {
            Some(ty @ (Ty::Int | Ty::UInt)) => ty,
            _ => return None,
        };
        let at = match offset {
            None => "0".to_string(),
            Some((offset, negated)) => {
                let offset = bare(self.expr_as(&offset, &Ty::Int));
                if negated {
                    format!("-({offset})")
                } else {
                    offset
                }
            }
        };
        Some((format!("{}[{at}]", ident(&self.global_name(&name))), ty))
    }

    /// `base[at]` of a parameter an atomic function works on, as WGSL (`counts[bin]`): what
    /// `atomicLoad`/`atomicStore` take. `None` for any other place.
    pub fn atomic_element(&mut self, place: &ast::Expr) -> Option<(String, Ty)> {
        let ast::Expr::IndexExpr(index) = place else { return None };
        let ast::Expr::NameExpr(base) = index.base()? else { return None };
        let name = base.name_ref()?.text();
        if !self.atomics.contains(&self.global_name(&name)) {
            return None;
        }
        let ty = self.params.get(&name).map(|p| element_type(&p.ty))?;
        let at = bare(self.expr_as(&index.index()?, &Ty::Int));
        Some((format!("{}[{at}]", ident(&self.global_name(&name))), ty))
    }
}

/// What a buffer or `shared` parameter's elements are.
fn element_type(ty: &Ty) -> Ty {
    match ty {
        Ty::Ref { inner, .. } | Ty::Array(inner) => element_type(inner),
        Ty::Gpu(name) if name.ends_with("ui") || name.ends_with("uc") || name.ends_with("us") => Ty::UInt,
        Ty::Gpu(name) if name.ends_with('i') || name.ends_with('c') || name.ends_with('s') => Ty::Int,
        other => other.clone(),
    }
}
