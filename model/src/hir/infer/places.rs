//! Where a body runs, and what it may use there: a `global` method has no object (no instance
//! field, no instance method, no `this`; 9.1.1, C++'s `static`), `Class::m(…)` needs a `global`
//! method unless it is device code (an `OpenCL` class is a namespace of kernels and helpers:
//! there are no objects on the device) or the owner's own (a C++ qualified call), and device code (an `OpenCL` class's) and host code call each other only
//! through calc and calcRange nodes (10.2.1.3, 10.3.2.3).

use super::InferenceCtx;
use crate::{
    hir::{definitions::Definition, diagnostics::DiagnosticCode, items::MethodSignature},
    library::OPENCL_INTERFACE,
    syntax::SyntaxNode,
};

/// What a body is, for the members and calls it may use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BodyRole {
    /// A method's, an activity node's or a diagram's: the owner's object is at hand.
    #[default]
    Ordinary,
    /// The body of a `global` method: there is no object.
    GlobalMethod,
    /// The body of a calc or calcRange node: it starts kernels.
    KernelLaunch,
}

/// How a call names its method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CallForm {
    /// `m(…)`: a method of the owner, on the body's object.
    Owner,
    /// `x.m(…)`: on an object.
    Object,
    /// `Class::m(…)`, `call Class::m(…)`: on no object.
    Class,
}

fn is_global(qualifiers: &[String]) -> bool {
    qualifiers.iter().any(|q| q == "global")
}

impl InferenceCtx<'_, '_> {
    /// Says what kind of body the context types.
    pub fn set_role(&mut self, role: BodyRole) {
        self.role = role;
    }

    /// `this`, or the owner's field `name` with `qualifiers`, used by a bare name: in a `global`
    /// method, only a `global` field.
    pub(super) fn expect_object(&mut self, name: &str, qualifiers: &[String], at: &SyntaxNode) {
        if self.role != BodyRole::GlobalMethod || is_global(qualifiers) {
            return;
        }
        let message = match name {
            "this" => {
                "a `global` method has no object: `this` names nothing here (drop `global` to have one)".to_string()
            }
            _ => format!(
                "`{name}` is a field of each object, and a `global` method has no object: pass the object as a \
                 parameter, declare `{name}` `global`, or drop `global` from the method"
            ),
        };
        self.sink.error(DiagnosticCode::NoObject, at.text_range(), message);
    }

    /// A call of `method`, declared by `declaring`, written in `form` at `at`: the object it
    /// needs is there, and it runs on the side (host or device) it is called from.
    pub(super) fn expect_callable_here(
        &mut self,
        form: CallForm,
        declaring: &Definition,
        method: &MethodSignature,
        at: &SyntaxNode,
    ) {
        if !self.expect_same_side(declaring, &method.name, at) {
            return;
        }
        if is_global(&method.qualifiers) || form == CallForm::Object {
            return;
        }
        let name = &method.name;
        let message = match (form, self.role) {
            (CallForm::Owner, BodyRole::GlobalMethod) => format!(
                "`{name}` is called on an object, and a `global` method has none: call it on an object \
                 (`x.{name}(…)`), declare `{name}` `global`, or drop `global` from this method"
            ),
            // Device code has no objects: an `OpenCL` class names its kernels and helpers.
            (CallForm::Class, _) if self.sema.is_gpu_class(declaring) => return,
            (CallForm::Class, BodyRole::Ordinary)
                if self.owner.is_some_and(|o| self.sema.is_subtype(&o.fqn, &declaring.fqn)) =>
            {
                return
            }
            (CallForm::Class, _) => format!(
                "`{name}` is not `global`: `{}::{name}(…)` has no object to call it on; call it on an object \
                 (`x.{name}(…)`) or declare `{name}` `global`",
                declaring.fqn
            ),
            _ => return,
        };
        self.sink.error(DiagnosticCode::NoObject, at.text_range(), message);
    }

    /// Device code calls device code, host code host code; host code starts device code only
    /// from a calc or calcRange node, which gives it a work size. Whether the call is allowed.
    fn expect_same_side(&mut self, declaring: &Definition, name: &str, at: &SyntaxNode) -> bool {
        let callee_on_device = self.sema.is_gpu_class(declaring);
        let here_on_device = self.owner.is_some_and(|o| self.sema.is_gpu_class(o));
        let message = match (callee_on_device, here_on_device) {
            (true, false) if self.role != BodyRole::KernelLaunch && declaring.fqn != OPENCL_INTERFACE => format!(
                "`{name}` is device code (`{}` implements `OpenCL`), called here from host code: start it from \
                 a `calc` or `calcRange` node (`call {0}::{name}(…)` in its body), which gives its work size",
                declaring.fqn
            ),
            (false, true) => format!(
                "`{}::{name}` is host code, and device code (an `OpenCL` class's) runs on the GPU, where it \
                 cannot be called: compute it on the device, or on the host before the kernel starts",
                declaring.fqn
            ),
            _ => return true,
        };
        self.sink.error(DiagnosticCode::DeviceHostCall, at.text_range(), message);
        false
    }
}
