//! Images on the device: `read_image{f,i,ui}` as OpenCL's sampler reads (integer coordinates
//! read as they are, clamped to the edge, or to the border colour; float coordinates normalised or not, repeated
//! or mirrored, nearest or linearly filtered — OpenCL 1.2, 8.2), written out as helpers per
//! image because WGSL samplers filter only float textures and address only what the hardware
//! has; `write_image…` and the image's size.
//!
//! A `sampler_t` is its flags as an `i32` (`sampler_flags`' values are OpenCL C's), so a sampler
//! may be a diagram's variable, a value computed in a node or a parameter the host passes; the
//! helpers branch on the flags, which the GPU's compiler folds where they are constant.

use gudsl_model::{
    ast::{self, AstNode},
    hir::Ty,
};

use crate::{
    emitter::{bare, ident, Emitter, GENERATED},
    types::convert,
    Binding, ImageType,
};

/// The bits of a sampler's addressing mode, and the values of the modes the helpers treat apart.
const ADDRESS_BITS: u32 = 0b1110;
const ADDRESS_NONE: u32 = 0;
const ADDRESS_CLAMP_TO_EDGE: u32 = 2;
const ADDRESS_CLAMP: u32 = 4;
const ADDRESS_REPEAT: u32 = 6;
const ADDRESS_MIRRORED_REPEAT: u32 = 8;
const NORMALIZED_COORDS: u32 = 1;
const FILTER_LINEAR: u32 = 32;

impl Emitter<'_> {
    /// `read_image{f,i,ui}(image, [sampler,] coordinate)` as the call's type.
    pub fn read_image(&mut self, call: &ast::CallExpr, args: &[ast::Expr], result: &Ty) -> String {
        let Some((name, image)) = args.first().and_then(|a| self.image_param(a)) else {
            return self.unsupported(call.syntax(), "the image must be a parameter of the diagram");
        };
        let (sampler, coordinate) = match args {
            [_, coordinate] => (None, coordinate),
            [_, sampler, coordinate] => (Some(sampler), coordinate),
            _ => return self.unsupported(call.syntax(), "read_image takes an image, a sampler and a coordinate"),
        };
        let Ty::Vector(element, width) = self.ty(coordinate).dereferenced().clone() else {
            return self.unsupported(coordinate.syntax(), "an image coordinate is an int2/float2 or int4/float4");
        };
        let dims = image.dimensions;
        let at = match (width, dims) {
            (2, 2) | (3, 3) => bare(self.expr(coordinate)),
            (4, 3) => format!("{}.xyz", self.expr(coordinate)),
            _ => {
                let message = format!("a {dims}D image takes an int{dims}/float{dims} coordinate");
                return self.unsupported(coordinate.syntax(), message);
            }
        };
        let written = matches!(self.binding(&name), Some(Binding::Image { written: true, .. }));
        let texture = ident(&self.global_name(&name));
        let read = match (element.as_ref(), sampler) {
            (Ty::Int, None) => {
                // No sampler: the texel, clamped to the image (OpenCL's sampler-less read).
                let ivec = format!("vec{dims}<i32>");
                let clamped = format!("clamp({at}, {ivec}(0), {ivec}(textureDimensions({texture})) - 1)");
                load(&texture, &clamped, written)
            }
            (Ty::Int | Ty::Float, Some(sampler)) => {
                let sampler = bare(self.expr_as(sampler, &Ty::Int));
                let float = *element == Ty::Float;
                *self.sampled_images.entry(self.global_name(&name)).or_default() |= float;
                let helper = if float { "sample" } else { "texel" };
                format!("{GENERATED}{helper}_{texture}({at}, {sampler})")
            }
            (Ty::Float, None) => {
                let message =
                    "a read at float coordinates goes through a sampler: read_imagef(image, sampler, coordinate)";
                return self.unsupported(call.syntax(), message);
            }
            _ => return self.unsupported(coordinate.syntax(), "an image coordinate is an int or a float vector"),
        };
        convert(read, &image.texel_ty(), result)
    }

    /// `write_image{f,i,ui}(image, coordinate, value)`.
    pub fn write_image(&mut self, call: &ast::CallExpr, args: &[ast::Expr]) -> String {
        let Some((name, image)) = args.first().and_then(|a| self.image_param(a)) else {
            return self.unsupported(call.syntax(), "the image must be a parameter of the diagram");
        };
        let [_, coordinate, value] = args else {
            return self.unsupported(call.syntax(), "write_image takes an image, a coordinate and a value");
        };
        let coordinate = match (self.ty(coordinate).dereferenced(), image.dimensions) {
            (Ty::Vector(_, 4), 3) => format!("{}.xyz", self.expr_as(coordinate, &Ty::Vector(Box::new(Ty::Int), 4))),
            (_, dims) => self.expr_as(coordinate, &Ty::Vector(Box::new(Ty::Int), dims)),
        };
        let value = self.expr_as(value, &image.texel_ty());
        format!("textureStore({}, {coordinate}, {value})", ident(&self.global_name(&name)))
    }

    /// `get_image_width|height|depth(image)`.
    pub fn image_size(&mut self, call: &ast::CallExpr, args: &[ast::Expr], axis: &str) -> String {
        let Some((image, _)) = args.first().and_then(|a| self.image_param(a)) else {
            return self.unsupported(call.syntax(), "the image must be a parameter of the diagram");
        };
        format!("i32(textureDimensions({}).{axis})", ident(&self.global_name(&image)))
    }

    /// The helpers of the reads through a sampler, per image.
    pub fn sampling_helpers(&self) -> String {
        let mut out = String::new();
        for (name, float) in &self.sampled_images {
            let Some(Binding::Image { image, written, .. }) = self.binding(name) else { continue };
            out.push_str(&texel_helper(&ident(name), image, *written));
            if *float {
                out.push_str(&sampling_helper(&ident(name), image));
            }
        }
        out
    }
}

/// `textureLoad` of a texture (a mip level) or of a storage texture (none).
fn load(texture: &str, at: &str, written: bool) -> String {
    match written {
        true => format!("textureLoad({texture}, {at})"),
        false => format!("textureLoad({texture}, {at}, 0)"),
    }
}

/// The texel at an integer coordinate through a sampler: with `CLK_ADDRESS_NONE` the texel
/// there, unchecked (OpenCL leaves a coordinate outside the image undefined; WGSL reads it
/// safely), which costs no more than a hand-written `textureLoad`; outside the image the border
/// colour (0) for `CLK_ADDRESS_CLAMP`, else the nearest edge texel.
fn texel_helper(texture: &str, image: &ImageType, written: bool) -> String {
    let (dims, texel) = (image.dimensions, image.texel);
    let ivec = format!("vec{dims}<i32>");
    let unchecked = load(texture, "at", written);
    let load = load(texture, &format!("clamp(at, {ivec}(0), size - 1)"), written);
    format!(
        "// A texel of `{texture}` through a sampler: with CLK_ADDRESS_NONE the texel there, unchecked;\n\
         // outside the image, the border colour (0) for CLK_ADDRESS_CLAMP, else the nearest edge texel.\n\
         fn {GENERATED}texel_{texture}(at: {ivec}, sampler: i32) -> vec4<{texel}> {{\n    \
         if (sampler & {ADDRESS_BITS}) == {ADDRESS_NONE} {{\n        \
         return {unchecked};\n    \
         }}\n    \
         let size = {ivec}(textureDimensions({texture}));\n    \
         if (sampler & {ADDRESS_BITS}) == {ADDRESS_CLAMP} && (any(at < {ivec}(0)) || any(at >= size)) {{\n        \
         return vec4<{texel}>();\n    \
         }}\n    \
         return {load};\n\
         }}\n\n"
    )
}

/// A read at a float coordinate through a sampler, as OpenCL 1.2's 8.2 computes it: the
/// coordinate in texels (scaled when normalised; folded into the image for repeat and mirrored
/// repeat), then the nearest texel or the weighted mean of the 2ᵈ around it (linear; integer
/// texels rounded to the nearest, where OpenCL leaves it undefined). `CLK_ADDRESS_NONE` reads
/// the texels like `CLK_ADDRESS_CLAMP_TO_EDGE`: filtering reaches past the edge.
fn sampling_helper(texture: &str, image: &ImageType) -> String {
    let (dims, texel) = (image.dimensions, image.texel);
    let (ivec, fvec, bvec) = (format!("vec{dims}<i32>"), format!("vec{dims}<f32>"), format!("vec{dims}<bool>"));
    let corners = 1 << dims;
    let far: Vec<String> = (0..dims).map(|d| format!("(corner & {}) != 0", 1 << d)).collect();
    let weight: Vec<&str> = ["weight.x", "weight.y", "weight.z"][..usize::from(dims)].to_vec();
    let result = match texel {
        "f32" => "sum".to_string(),
        _ => format!("vec4<{texel}>(round(sum))"),
    };
    format!(
        "// read_image… of `{texture}` at a float coordinate through a sampler (OpenCL 1.2, 8.2).\n\
         fn {GENERATED}sample_{texture}(coordinate: {fvec}, sampler: i32) -> vec4<{texel}> {{\n    \
         let size = {ivec}(textureDimensions({texture}));\n    \
         let extent = {fvec}(size);\n    \
         let address = sampler & {ADDRESS_BITS};\n    \
         let texels = select(sampler, sampler | {ADDRESS_CLAMP_TO_EDGE}, address == {ADDRESS_NONE});\n    \
         // The coordinate normalised (s) and in texels (u); repeat and mirrored repeat fold it in.\n    \
         var s = coordinate;\n    \
         var u = coordinate;\n    \
         if (sampler & {NORMALIZED_COORDS}) != 0 {{ u = s * extent; }} else {{ s = u / extent; }}\n    \
         if address == {ADDRESS_REPEAT} {{ u = (s - floor(s)) * extent; }}\n    \
         if address == {ADDRESS_MIRRORED_REPEAT} {{ u = abs(s - 2.0 * round(0.5 * s)) * extent; }}\n    \
         if (sampler & {FILTER_LINEAR}) == 0 {{\n        \
         var i = {ivec}(floor(u));\n        \
         if address == {ADDRESS_REPEAT} {{ i = select(i, i - size, i > size - 1); }}\n        \
         if address == {ADDRESS_MIRRORED_REPEAT} {{ i = min(i, size - 1); }}\n        \
         return {GENERATED}texel_{texture}(i, texels);\n    \
         }}\n    \
         let before = u - 0.5;\n    \
         var i0 = {ivec}(floor(before));\n    \
         var i1 = i0 + 1;\n    \
         let a = before - floor(before);\n    \
         if address == {ADDRESS_REPEAT} {{\n        \
         i0 = select(i0, i0 + size, i0 < {ivec}(0));\n        \
         i1 = select(i1, i1 - size, i1 > size - 1);\n    \
         }}\n    \
         if address == {ADDRESS_MIRRORED_REPEAT} {{\n        \
         i0 = max(i0, {ivec}(0));\n        \
         i1 = min(i1, size - 1);\n    \
         }}\n    \
         var sum = vec4<f32>();\n    \
         for (var corner = 0; corner < {corners}; corner++) {{\n        \
         let far = {bvec}({far});\n        \
         let weight = select(1.0 - a, a, far);\n        \
         sum += {weights} * vec4<f32>({GENERATED}texel_{texture}(select(i0, i1, far), texels));\n    \
         }}\n    \
         return {result};\n\
         }}\n\n",
        far = far.join(", "),
        weights = weight.join(" * "),
    )
}
