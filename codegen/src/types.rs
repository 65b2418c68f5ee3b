//! GU-DSL types in WGSL: scalars and vectors of 10.2.1.5, the texel formats of typed images,
//! and the conversions C performs implicitly that WGSL wants written.

use gudsl_model::hir::Ty;

use crate::emitter::bare;

/// The WGSL type of a value type: `int` → `i32`, `uint4` → `vec4<u32>`, a `sampler_t` its flags
/// (`i32`, `images.rs`); `None` for what WGSL has no value type for (vectors of 8 or 16,
/// strings, classes).
pub fn value_type(ty: &Ty) -> Option<String> {
    match ty.dereferenced() {
        Ty::Bool => Some("bool".into()),
        Ty::Int => Some("i32".into()),
        Ty::UInt => Some("u32".into()),
        Ty::Float => Some("f32".into()),
        Ty::Vector(base, n @ 2..=4) => Some(format!("vec{n}<{}>", value_type(base)?)),
        Ty::Gpu(name) if name == "sampler_t" => Some("i32".into()),
        _ => None,
    }
}

/// C's usual arithmetic conversions for two operands: the type both are converted to.
pub fn common(a: &Ty, b: &Ty) -> Ty {
    let (a, b) = (a.dereferenced(), b.dereferenced());
    match (a, b) {
        (Ty::Vector(x, n), Ty::Vector(y, _)) => Ty::Vector(Box::new(common(x, y)), *n),
        (Ty::Vector(x, n), s) | (s, Ty::Vector(x, n)) => Ty::Vector(Box::new(common(x, s)), *n),
        (Ty::Float, _) | (_, Ty::Float) => Ty::Float,
        (Ty::UInt, _) | (_, Ty::UInt) => Ty::UInt,
        (Ty::Int, _) | (_, Ty::Int) => Ty::Int,
        (Ty::Bool, Ty::Bool) => Ty::Int,
        _ => a.clone(),
    }
}

/// `code`, of type `from`, as a value of type `to` (C's implicit conversions: numbers convert,
/// a scalar widens to a vector, a number is true when it is not zero).
pub fn convert(code: String, from: &Ty, to: &Ty) -> String {
    let (from, to) = (from.dereferenced(), to.dereferenced());
    if from == to || matches!(from, Ty::Unknown) || matches!(to, Ty::Unknown) {
        return code;
    }
    let Some(target) = value_type(to) else { return code };
    if value_type(from).as_ref() == Some(&target) {
        // The same WGSL type (a `sampler_t` is an `int`).
        return code;
    }
    match (from, to) {
        (_, Ty::Bool) => match from {
            Ty::Int => format!("({code} != 0)"),
            Ty::UInt => format!("({code} != 0u)"),
            Ty::Float => format!("({code} != 0.0)"),
            _ => code,
        },
        (Ty::Bool, _) => format!("select({}, {}, {code})", zero(to), one(to)),
        (Ty::Vector(..), Ty::Vector(..)) => format!("{target}({})", bare(code)),
        (_, Ty::Vector(base, _)) => format!("{target}({})", bare(convert(code, from, base))),
        _ => format!("{target}({})", bare(code)),
    }
}

/// The zero of a numeric type, as WGSL.
fn zero(ty: &Ty) -> String {
    literal(ty, "0")
}

fn one(ty: &Ty) -> String {
    literal(ty, "1")
}

/// A small integer literal of a numeric type: `0`, `0u`, `0.0`, `vec4<f32>(0.0)`.
fn literal(ty: &Ty, digits: &str) -> String {
    match ty {
        Ty::Int => format!("{digits}i"),
        Ty::UInt => format!("{digits}u"),
        Ty::Float => format!("{digits}.0"),
        Ty::Vector(base, _) => format!("{}({})", value_type(ty).unwrap_or_default(), literal(base, digits)),
        _ => digits.into(),
    }
}

/// A typed image (`image2D_uc`, `image3D_f`): its dimension and the storage texel format of its
/// element type, with the WGSL scalar of its texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageType {
    pub dimensions: u8,
    pub format: &'static str,
    pub texel: &'static str,
}

impl ImageType {
    /// The image type named `name`; `None` for other names and for OpenCL's untyped
    /// `image2D_t`, which has no format to give a storage texture.
    pub fn parse(name: &str) -> Option<ImageType> {
        let (dimensions, suffix) = match name.strip_prefix("image2D_") {
            Some(suffix) => (2, suffix),
            None => (3, name.strip_prefix("image3D_")?),
        };
        let (format, texel) = match suffix {
            "uc" => ("rgba8uint", "u32"),
            "c" => ("rgba8sint", "i32"),
            "us" => ("rgba16uint", "u32"),
            "s" => ("rgba16sint", "i32"),
            "ui" => ("rgba32uint", "u32"),
            "i" => ("rgba32sint", "i32"),
            "f" => ("rgba32float", "f32"),
            _ => return None,
        };
        Some(ImageType { dimensions, format, texel })
    }

    /// The GU-DSL type of one texel as WGSL returns it (`uint4` for `uc`).
    pub fn texel_ty(&self) -> Ty {
        let base = match self.texel {
            "u32" => Ty::UInt,
            "i32" => Ty::Int,
            _ => Ty::Float,
        };
        Ty::Vector(Box::new(base), 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(base: Ty, n: u8) -> Ty {
        Ty::Vector(Box::new(base), n)
    }

    #[test]
    fn value_types_and_conversions() {
        assert_eq!(value_type(&v(Ty::UInt, 4)).as_deref(), Some("vec4<u32>"));
        assert_eq!(value_type(&v(Ty::Float, 8)), None, "WGSL has no 8-wide vectors");
        assert_eq!(common(&Ty::Int, &Ty::Float), Ty::Float);
        assert_eq!(common(&Ty::Int, &Ty::UInt), Ty::UInt);
        assert_eq!(common(&v(Ty::Float, 3), &Ty::Int), v(Ty::Float, 3));
        assert_eq!(convert("x".into(), &Ty::Int, &Ty::Float), "f32(x)");
        assert_eq!(convert("x".into(), &Ty::Int, &v(Ty::Float, 3)), "vec3<f32>(f32(x))");
        assert_eq!(convert("x".into(), &Ty::Int, &Ty::Bool), "(x != 0)");
        assert_eq!(convert("b".into(), &Ty::Bool, &Ty::Int), "select(0i, 1i, b)");
        assert_eq!(convert("x".into(), &Ty::Float, &Ty::Float), "x");
    }

    #[test]
    fn image_types() {
        let uc = ImageType::parse("image2D_uc").unwrap();
        assert_eq!((uc.dimensions, uc.format, uc.texel), (2, "rgba8uint", "u32"));
        assert_eq!(ImageType::parse("image3D_f").unwrap().format, "rgba32float");
        assert_eq!(ImageType::parse("image2D_t"), None);
    }
}
