//! Types of the expression language, as far as checks need them: primitives, GPU vectors and
//! images, user types by fully qualified name, and `Unknown` for whatever cannot be known (which
//! is compatible with everything, so one unresolved name never cascades into more errors).

use std::fmt;

use super::items::TypeSignature;

/// A type.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Ty {
    Unknown,
    Void,
    Bool,
    /// `byte`, `char`, `short`, `int`, `long`.
    Int,
    /// Their `unsigned` forms (`unsigned int`, `uint`, `uchar`, …).
    UInt,
    /// `float`, `real`, `double`.
    Float,
    String,
    Null,
    /// `float4`, `int2`, `uchar16`, …: element kind and width.
    Vector(Box<Ty>, u8),
    /// `image2D_uc`, `buffer2D_f4`, `sampler_t`: opaque GPU types.
    Gpu(std::string::String),
    /// A declared class, interface or enum, by fully qualified name.
    Named(std::string::String),
    Array(Box<Ty>),
    /// `ref T` and `global ref T`: memory that holds a `T` (a kernel's buffer parameter, a
    /// host pointer). A `T`, an array of `T` and `null` bind to it; a host container binds to
    /// a `global` one (the framework's KernelCall hands over its device memory, Sec. 10.3.1).
    Ref {
        global: bool,
        inner: Box<Ty>,
    },
}

impl Ty {
    pub fn is_numeric(&self) -> bool {
        matches!(self, Ty::Int | Ty::UInt | Ty::Float)
    }

    /// The type a reference refers to; the type itself otherwise.
    pub fn dereferenced(&self) -> &Ty {
        match self {
            Ty::Ref { inner, .. } => inner,
            other => other,
        }
    }

    /// Whether a value of type `self` may be assigned to (or passed as) `target`. Numbers convert
    /// into each other as in C; `ref`/`out` and user types are compared by name only when both
    /// sides are known; inheritance is the caller's business (`subtype`).
    pub fn assignable_to(&self, target: &Ty, subtype: &mut dyn FnMut(&str, &str) -> bool) -> bool {
        match (self, target) {
            (Ty::Unknown, _) | (_, Ty::Unknown) => true,
            (a, b) if a == b => true,
            (Ty::Null, Ty::Ref { .. }) => true,
            // A host container's device memory binds to a kernel's `global ref T`.
            (Ty::Named(_), Ty::Ref { global: true, .. }) => true,
            (Ty::Ref { inner: a, .. }, Ty::Ref { inner: b, .. }) => a.assignable_to(b, subtype),
            // A value (or an array of them) binds to a reference; a reference reads as its value.
            (a, Ty::Ref { inner, .. }) => a.assignable_to(inner, subtype),
            (Ty::Ref { inner, .. }, b) => inner.assignable_to(b, subtype),
            (a, b) if a.is_numeric() && b.is_numeric() => true,
            // C's implicit conversions between numbers and booleans.
            (Ty::Bool, b) | (b, Ty::Bool) if b.is_numeric() => true,
            (Ty::Null, Ty::Named(_) | Ty::Array(_) | Ty::Gpu(_) | Ty::String) => true,
            // A scalar broadcasts into a vector (`float4 x = 0.0f`), as OpenCL allows.
            (a, Ty::Vector(..)) if a.is_numeric() => true,
            (Ty::Vector(a, n), Ty::Vector(b, m)) => n == m && (a == b || (a.is_numeric() && b.is_numeric())),
            (Ty::Named(a), Ty::Named(b)) => subtype(a, b),
            // Arrays and references stand for memory: an array of T passes where T is expected.
            (Ty::Array(a), b) | (b, Ty::Array(a)) => a.assignable_to(b, subtype) || b.assignable_to(a, subtype),
            // The framework's C++ types are often passed through `void` references.
            (_, Ty::Void) => true,
            // A host container passed to a kernel's image or buffer parameter: the framework's
            // KernelCall hands over its device memory (Sec. 10.3.1).
            (Ty::Named(_), Ty::Gpu(_)) => true,
            // `image2D_t` / `image3D_t` (the library's built-ins take them): any image of that
            // dimension, whatever its texel type.
            (Ty::Gpu(image), Ty::Gpu(any)) => {
                any.strip_suffix("_t").is_some_and(|kind| image.strip_prefix(kind).is_some_and(|t| t.starts_with('_')))
            }
            _ => false,
        }
    }
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ty::Unknown => write!(f, "?"),
            Ty::Void => write!(f, "void"),
            Ty::Bool => write!(f, "bool"),
            Ty::Int => write!(f, "int"),
            Ty::UInt => write!(f, "unsigned int"),
            Ty::Float => write!(f, "float"),
            Ty::String => write!(f, "string"),
            Ty::Null => write!(f, "null"),
            Ty::Vector(base, n) => match **base {
                Ty::UInt => write!(f, "uint{n}"),
                _ => write!(f, "{base}{n}"),
            },
            Ty::Gpu(name) | Ty::Named(name) => write!(f, "{name}"),
            Ty::Array(inner) => write!(f, "{inner}[]"),
            Ty::Ref { global: true, inner } => write!(f, "global ref {inner}"),
            Ty::Ref { global: false, inner } => write!(f, "ref {inner}"),
        }
    }
}

/// The type of a built-in keyword or GPU type name, if it is one.
pub fn builtin(name: &str) -> Option<Ty> {
    Some(match name {
        "bool" => Ty::Bool,
        "byte" | "char" | "short" | "int" | "long" => Ty::Int,
        "uchar" | "ushort" | "uint" | "ulong" => Ty::UInt,
        "float" | "real" | "double" => Ty::Float,
        "string" => Ty::String,
        "void" => Ty::Void,
        _ => {
            for (prefix, base) in [
                ("uchar", Ty::UInt),
                ("ushort", Ty::UInt),
                ("uint", Ty::UInt),
                ("ulong", Ty::UInt),
                ("char", Ty::Int),
                ("short", Ty::Int),
                ("int", Ty::Int),
                ("long", Ty::Int),
                ("float", Ty::Float),
                ("double", Ty::Float),
            ] {
                if let Some(width) = name.strip_prefix(prefix).and_then(|w| w.parse::<u8>().ok()) {
                    if [2, 3, 4, 8, 16].contains(&width) {
                        return Some(Ty::Vector(Box::new(base), width));
                    }
                }
            }
            if is_builtin_type_name(name) {
                return Some(Ty::Gpu(name.to_string()));
            }
            return None;
        }
    })
}

/// The type a signature denotes, given how to resolve a path to a fully qualified name.
pub fn from_signature(sig: &TypeSignature, resolve: &mut dyn FnMut(&str) -> Option<String>) -> Ty {
    let base = if let Some(builtin_name) = &sig.builtin {
        match builtin(builtin_name).unwrap_or(Ty::Unknown) {
            Ty::Int if sig.is_unsigned => Ty::UInt,
            ty => ty,
        }
    } else if sig.is_unsigned && sig.path.is_none() {
        Ty::UInt
    } else if let Some(path) = &sig.path {
        builtin(path).or_else(|| resolve(path).map(Ty::Named)).unwrap_or(Ty::Unknown)
    } else {
        Ty::Unknown
    };
    let ty = (0..sig.array_dims).fold(base, |ty, _| Ty::Array(Box::new(ty)));
    match sig.is_ref {
        true => Ty::Ref { global: sig.is_global, inner: Box::new(ty) },
        false => ty,
    }
}

/// GPU and OpenCL built-in type names of chapter 10 that are written as identifiers:
/// `(u)char|short|int|long|float|double` with n ∈ {2,3,4,8,16} (and the scalar `uchar`…),
/// `image2D_t`, `image3D_t` (the text's typed images: `t` a texel type such as `uc`; the
/// literal `image2D_t`/`image3D_t` are OpenCL's untyped ones, any image of that dimension),
/// `buffer2D_tn`, `buffer3D_tn`, `sampler_t`.
/// The built-in type names a typo is most likely of: the keyword types and the common
/// vectors, images and samplers ("did you mean `int`?" for `intt`).
pub fn common_builtin_type_names() -> Vec<String> {
    let keywords = ["bool", "byte", "char", "double", "float", "int", "long", "real", "short", "string", "void"];
    let mut names: Vec<String> = keywords.iter().map(|k| k.to_string()).collect();
    for scalar in ["char", "uchar", "int", "uint", "float"] {
        names.extend(["2", "3", "4"].iter().map(|width| format!("{scalar}{width}")));
    }
    names.extend(["image2D_t", "image3D_t", "sampler_t"].iter().map(|n| n.to_string()));
    names
}

pub fn is_builtin_type_name(name: &str) -> bool {
    const SCALARS: [&str; 6] = ["char", "short", "int", "long", "float", "double"];
    const SUFFIXES: [&str; 10] = ["c", "uc", "s", "us", "i", "ui", "l", "ul", "f", "d"];
    const WIDTHS: [&str; 5] = ["2", "3", "4", "8", "16"];
    if matches!(name, "sampler_t" | "image2D_t" | "image3D_t") {
        return true;
    }
    let vector =
        |rest: &str| SCALARS.iter().any(|s| rest.strip_prefix(s).is_some_and(|n| n.is_empty() || WIDTHS.contains(&n)));
    if vector(name) || name.strip_prefix('u').is_some_and(|r| r.starts_with(['c', 's', 'i', 'l']) && vector(r)) {
        return true;
    }
    for prefix in ["image2D_", "image3D_"] {
        if name.strip_prefix(prefix).is_some_and(|t| SUFFIXES.contains(&t)) {
            return true;
        }
    }
    for prefix in ["buffer2D_", "buffer3D_"] {
        if let Some(rest) = name.strip_prefix(prefix) {
            if SUFFIXES.iter().any(|s| rest.strip_prefix(s).is_some_and(|n| WIDTHS.contains(&n))) {
                return true;
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    #[test]
    fn gpu_type_names() {
        for yes in [
            "float4",
            "uchar16",
            "int2",
            "uint",
            "double8",
            "image2D_uc",
            "image3D_f",
            "buffer2D_ui4",
            "buffer3D_d16",
            "sampler_t",
            "image2D_t",
        ] {
            assert!(super::is_builtin_type_name(yes), "{yes}");
        }
        for no in ["float5", "image2D_x", "buffer2D_f", "Image", "uchar5", "ufloat4"] {
            assert!(!super::is_builtin_type_name(no), "{no}");
        }
    }

    #[test]
    fn any_image_of_a_dimension_passes_as_its_untyped_image() {
        use super::Ty;
        let gpu = |n: &str| Ty::Gpu(n.to_string());
        let fits = |a: &str, b: &str| gpu(a).assignable_to(&gpu(b), &mut |_, _| false);
        assert!(fits("image2D_uc", "image2D_t"));
        assert!(fits("image3D_f", "image3D_t"));
        assert!(!fits("image3D_f", "image2D_t"));
        assert!(!fits("buffer2D_f4", "image2D_t"));
        assert!(!fits("image2D_t", "image2D_uc"));
        assert!(!fits("image2D_uc", "image2D_f"));
    }
}
