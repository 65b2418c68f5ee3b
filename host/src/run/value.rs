//! The host interpreter's values: C's `int` and `unsigned int` (32 bits, wrapping), floating
//! point, booleans, strings, pointers into host memory (typed by their element, as C pointers
//! are), framework objects (`QImage`, the viewer, the heterogeneous computing containers with
//! their host copy and device memory; `framework.rs` runs their methods) and `null`.

use std::{cell::RefCell, fmt, rc::Rc, sync::Arc};

use gudsl_runtime::{DeviceBuffer, DeviceImage, Gpu, TexelFormat};

use gudsl_model::ast::{self, AstNode};

/// A scalar as it is stored in host memory: what a pointer's element is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// Bytes of one element.
    #[inline(always)]
    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The element a written type denotes: `unsigned byte` → `U8`, `int` → `I32`, `uchar`,
    /// `float`, …; `void` and everything else (classes) are bytes.
    pub fn of_type_ref(ty: &ast::TypeRef) -> Scalar {
        let unsigned = ty.is_unsigned();
        let name = match ty.path() {
            Some(path) => path.text(),
            None => ty
                .syntax()
                .children_with_tokens()
                .filter_map(|t| t.into_token())
                .filter(|t| t.kind().is_keyword() && !matches!(t.text(), "ref" | "unsigned"))
                .map(|t| t.text().to_string())
                .last()
                .unwrap_or_default(),
        };
        Scalar::named(&name, unsigned)
    }

    /// The element called `name` (`unsigned` written before it or not).
    pub fn named(name: &str, unsigned: bool) -> Scalar {
        let signed = match name {
            "bool" | "byte" | "char" | "void" => Scalar::I8,
            "uchar" => return Scalar::U8,
            "short" => Scalar::I16,
            "ushort" => return Scalar::U16,
            "int" | "long" => Scalar::I32,
            "uint" | "ulong" => return Scalar::U32,
            "float" | "real" => return Scalar::F32,
            "double" => return Scalar::F64,
            _ => Scalar::U8,
        };
        match (signed, unsigned || name == "void") {
            (Scalar::I8, true) => Scalar::U8,
            (Scalar::I16, true) => Scalar::U16,
            (Scalar::I32, true) => Scalar::U32,
            (other, _) => other,
        }
    }

    /// The number stored in `bytes` (exactly [`Scalar::size`] of them).
    #[inline(always)]
    fn load(self, bytes: &[u8]) -> Number {
        let array = |n: usize| {
            let mut out = [0u8; 8];
            out[..n].copy_from_slice(&bytes[..n]);
            out
        };
        match self {
            Scalar::I8 => Number::Int(bytes[0] as i8 as i64),
            Scalar::U8 => Number::Int(bytes[0] as i64),
            Scalar::I16 => Number::Int(i16::from_le_bytes([bytes[0], bytes[1]]) as i64),
            Scalar::U16 => Number::Int(u16::from_le_bytes([bytes[0], bytes[1]]) as i64),
            Scalar::I32 => Number::Int(i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64),
            Scalar::U32 => Number::Int(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64),
            Scalar::F32 => Number::Float(f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64),
            Scalar::F64 => Number::Float(f64::from_le_bytes(array(8))),
        }
    }

    /// An element's number as the interpreter's value: `int`, `unsigned int` or floating point.
    fn value(self, number: Number) -> Value {
        match (self, number) {
            (Scalar::U8 | Scalar::U16 | Scalar::U32, Number::Int(v)) => Value::UInt(v as u32),
            (_, Number::Int(v)) => Value::Int(v as i32),
            (_, Number::Float(v)) => Value::Float(v),
        }
    }

    /// Writes `number`, converted as C converts on assignment, into `bytes`.
    #[inline(always)]
    fn store(self, number: Number, bytes: &mut [u8]) {
        match self {
            Scalar::I8 | Scalar::U8 => bytes[0] = number.as_i64() as u8,
            Scalar::I16 | Scalar::U16 => bytes[..2].copy_from_slice(&(number.as_i64() as u16).to_le_bytes()),
            Scalar::I32 | Scalar::U32 => bytes[..4].copy_from_slice(&(number.as_i64() as u32).to_le_bytes()),
            Scalar::F32 => bytes[..4].copy_from_slice(&(number.as_f64() as f32).to_le_bytes()),
            Scalar::F64 => bytes[..8].copy_from_slice(&number.as_f64().to_le_bytes()),
        }
    }
}

/// A block of host memory (`new unsigned int[n]`, an image's pixels, a container's host copy).
pub type Memory = Rc<RefCell<Vec<u8>>>;

/// A fresh zeroed block of `bytes` bytes.
pub fn memory(bytes: usize) -> Memory {
    Rc::new(RefCell::new(vec![0; bytes]))
}

/// A C pointer: a block, a byte offset into it and the element it points to.
#[derive(Clone)]
pub struct Pointer {
    pub memory: Memory,
    pub offset: i64,
    pub element: Scalar,
}

impl Pointer {
    pub fn to(memory: Memory, element: Scalar) -> Pointer {
        Pointer { memory, offset: 0, element }
    }

    /// `p + n`: `n` elements further.
    pub fn add(&self, elements: i64) -> Pointer {
        Pointer { offset: self.offset + elements * self.element.size() as i64, ..self.clone() }
    }

    /// The same address, read as `element`s (`p as ref int`).
    pub fn cast(&self, element: Scalar) -> Pointer {
        Pointer { element, ..self.clone() }
    }

    /// The byte range of element `index` in a block of `len` bytes, if it lies inside.
    #[inline(always)]
    fn at(&self, index: i64, len: usize) -> Option<std::ops::Range<usize>> {
        let size = self.element.size() as i64;
        let start = self.offset.checked_add(index.checked_mul(size)?)?;
        (start >= 0 && start + size <= len as i64).then_some(start as usize..(start + size) as usize)
    }

    /// Why element `index` cannot be read or written.
    #[cold]
    pub fn outside(&self, index: i64) -> String {
        let size = self.element.size() as i64;
        let len = self.memory.borrow().len() as i64;
        format!(
            "element {index} is outside the memory it points into ({} element(s) of {size} byte(s) from the pointer)",
            (len - self.offset).max(0) / size
        )
    }

    /// `p[index]` as a number: what the interpreter's arithmetic reads without making a value.
    #[inline(always)]
    pub fn load(&self, index: i64) -> Result<Number, String> {
        let memory = self.memory.borrow();
        match self.at(index, memory.len()) {
            Some(range) => Ok(self.element.load(&memory[range])),
            None => Err(self.outside(index)),
        }
    }

    /// `p[index] = number`.
    #[inline(always)]
    pub fn store(&self, index: i64, number: Number) -> Result<(), String> {
        let mut memory = self.memory.borrow_mut();
        match self.at(index, memory.len()) {
            Some(range) => {
                self.element.store(number, &mut memory[range]);
                Ok(())
            }
            None => {
                drop(memory);
                Err(self.outside(index))
            }
        }
    }

    /// `p[index]`.
    pub fn read(&self, index: i64) -> Result<Value, String> {
        self.load(index).map(|number| self.element.value(number))
    }

    /// `p[index] = value`.
    pub fn write(&self, index: i64, value: &Value) -> Result<(), String> {
        let number =
            value.number().ok_or_else(|| format!("a {} cannot be stored in memory of numbers", value.kind()))?;
        self.store(index, number)
    }

    /// A copy of `bytes` bytes from the pointer on.
    pub fn bytes(&self, bytes: usize) -> Result<Vec<u8>, String> {
        let start = self.offset;
        let len = self.memory.borrow().len() as i64;
        if start < 0 || start + bytes as i64 > len {
            return Err(format!("{bytes} bytes from the pointer: only {} are there", (len - start).max(0)));
        }
        Ok(self.memory.borrow()[start as usize..start as usize + bytes].to_vec())
    }

    /// Copies `bytes` into memory from the pointer on.
    pub fn put(&self, bytes: &[u8]) -> Result<(), String> {
        let start = self.offset;
        let len = self.memory.borrow().len() as i64;
        if start < 0 || start + bytes.len() as i64 > len {
            return Err(format!("{} bytes to the pointer: only {} fit", bytes.len(), (len - start).max(0)));
        }
        self.memory.borrow_mut()[start as usize..start as usize + bytes.len()].copy_from_slice(bytes);
        Ok(())
    }
}

/// A value known before a run (a literal, a variable's first value): what a lowered program
/// holds, so that it can move to the thread that runs it.
#[derive(Debug, Clone, PartialEq)]
pub enum Constant {
    Void,
    Null,
    Bool(bool),
    Int(i32),
    UInt(u32),
    Float(f64),
    Str(Arc<str>),
}

impl Constant {
    pub fn value(&self) -> Value {
        match self {
            Constant::Void => Value::Void,
            Constant::Null => Value::Null,
            Constant::Bool(v) => Value::Bool(*v),
            Constant::Int(v) => Value::Int(*v),
            Constant::UInt(v) => Value::UInt(*v),
            Constant::Float(v) => Value::Float(*v),
            Constant::Str(v) => Value::Str(v.clone()),
        }
    }

    /// The constant a value is, if it is one (no pointer, no object).
    pub fn of(value: Value) -> Option<Constant> {
        Some(match value {
            Value::Void => Constant::Void,
            Value::Null => Constant::Null,
            Value::Bool(v) => Constant::Bool(v),
            Value::Int(v) => Constant::Int(v),
            Value::UInt(v) => Constant::UInt(v),
            Value::Float(v) => Constant::Float(v),
            Value::Str(v) => Constant::Str(v),
            Value::Ptr(_) | Value::Object(_) => return None,
        })
    }
}

/// A value of the host interpreter. Its tag is a whole word: a value made on the stack and
/// copied into the frame is then read back as it was written (a tag written as one byte and
/// read back within a word stalls the store-to-load forwarding of the processor — measured,
/// docs/host.md).
#[derive(Clone, Default)]
#[repr(u64)]
pub enum Value {
    /// What a `void` call gives, and a variable not yet assigned.
    #[default]
    Void,
    Null,
    Bool(bool),
    /// `int` (also `char`, `short`, `long` and enum constants, as C computes them).
    Int(i32),
    UInt(u32),
    Float(f64),
    Str(Arc<str>),
    Ptr(Pointer),
    Object(Rc<RefCell<Object>>),
}

/// A number, for conversions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub fn as_i64(self) -> i64 {
        match self {
            Number::Int(v) => v,
            Number::Float(v) => v as i64,
        }
    }

    pub fn as_f64(self) -> f64 {
        match self {
            Number::Int(v) => v as f64,
            Number::Float(v) => v,
        }
    }
}

/// Setting a variable to a number: in place when it holds a number of that kind already (the
/// interpreter's hot path: no value is made and copied, nothing is dropped).
macro_rules! setter {
    ($name:ident, $variant:ident, $ty:ty) => {
        #[inline(always)]
        pub fn $name(&mut self, value: $ty) {
            match self {
                Value::$variant(old) => *old = value,
                other => *other = Value::$variant(value),
            }
        }
    };
}

impl Value {
    setter!(set_int, Int, i32);
    setter!(set_uint, UInt, u32);
    setter!(set_float, Float, f64);
    setter!(set_bool, Bool, bool);
}

impl Value {
    /// The number a value is, if it is one (`bool` is 0 or 1).
    pub fn number(&self) -> Option<Number> {
        Some(match self {
            Value::Bool(b) => Number::Int(*b as i64),
            Value::Int(v) => Number::Int(*v as i64),
            Value::UInt(v) => Number::Int(*v as i64),
            Value::Float(v) => Number::Float(*v),
            _ => return None,
        })
    }

    /// What kind of value it is, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Void => "value not set",
            Value::Null => "null",
            Value::Bool(_) => "bool",
            Value::Int(_) => "int",
            Value::UInt(_) => "unsigned int",
            Value::Float(_) => "float",
            Value::Str(_) => "string",
            Value::Ptr(_) => "pointer",
            Value::Object(object) => object.borrow().class(),
        }
    }
}

impl fmt::Debug for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Void => write!(f, "void"),
            Value::Null => write!(f, "null"),
            Value::Bool(v) => write!(f, "{v}"),
            Value::Int(v) => write!(f, "{v}"),
            Value::UInt(v) => write!(f, "{v}u"),
            Value::Float(v) => write!(f, "{v}"),
            Value::Str(v) => write!(f, "{v:?}"),
            Value::Ptr(p) => write!(f, "pointer({:?} at byte {})", p.element, p.offset),
            Value::Object(object) => write!(f, "{}", object.borrow().class()),
        }
    }
}

impl Value {
    /// Element `index` of what the value points to or holds on the host: a pointer's memory,
    /// an `ImageContainer`'s or `BufferContainer`'s host copy.
    pub fn element(&self, index: i64) -> Option<Value> {
        match self {
            Value::Ptr(pointer) => pointer.read(index).ok(),
            Value::Object(object) => object.borrow().host()?.read(index).ok(),
            _ => None,
        }
    }
}

/// A framework object.
pub enum Object {
    Image(QImage),
    Viewer(Viewer),
    Images(ImageContainer),
    Buffer(BufferContainer),
    Device { max_work_group_size: u32 },
}

impl Object {
    pub fn class(&self) -> &'static str {
        match self {
            Object::Image(_) => "QImage",
            Object::Viewer(_) => "Viewer2D",
            Object::Images(_) => "ImageContainer",
            Object::Buffer(_) => "BufferContainer",
            Object::Device { .. } => "HCDevicePtr",
        }
    }

    /// A container's host copy, as a pointer to its elements.
    pub fn host(&self) -> Option<Pointer> {
        match self {
            Object::Images(c) => Some(Pointer::to(c.host.clone(), c.element)),
            Object::Buffer(c) => Some(Pointer::to(c.host.clone(), c.element)),
            _ => None,
        }
    }
}

/// A `QImage`: 8-bit RGBA pixels, rows top to bottom (a null image has no pixels). Its scan
/// lines hold R, G, B, A in that order, the channel order the listings' containers declare
/// (Qt keeps `Format_ARGB32` as B, G, R, A in memory; the listings' images are grey).
#[derive(Clone)]
pub struct QImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Memory,
}

/// A `Viewer2D`: its image objects, each the last image it was given.
pub struct Viewer {
    pub number: usize,
    pub images: Vec<Option<Shown>>,
}

/// An image a viewer shows: RGB or grey bytes, rows top to bottom.
pub struct Shown {
    pub width: u32,
    pub height: u32,
    pub channels: u8,
    pub bytes: Vec<u8>,
}

/// An `ImageContainer<T>`: four channels of `T` per pixel, on the host and on the device.
pub struct ImageContainer {
    pub label: String,
    pub element: Scalar,
    pub width: u32,
    pub height: u32,
    pub host: Memory,
    pub device: Option<DeviceImage>,
}

/// A `BufferContainer<T>`: `len` elements of `T`, on the host and on the device.
pub struct BufferContainer {
    pub label: String,
    pub element: Scalar,
    pub len: u64,
    pub host: Memory,
    pub device: Option<DeviceBuffer>,
}

impl ImageContainer {
    pub fn format(&self) -> Result<TexelFormat, String> {
        Ok(match self.element {
            Scalar::U8 => TexelFormat::Rgba8Uint,
            Scalar::I8 => TexelFormat::Rgba8Sint,
            Scalar::U16 => TexelFormat::Rgba16Uint,
            Scalar::I16 => TexelFormat::Rgba16Sint,
            Scalar::U32 => TexelFormat::Rgba32Uint,
            Scalar::I32 => TexelFormat::Rgba32Sint,
            Scalar::F32 => TexelFormat::Rgba32Float,
            Scalar::F64 => return Err("images of `double` have no device format; use `float`".into()),
        })
    }

    pub fn bytes(&self) -> usize {
        self.width as usize * self.height as usize * 4 * self.element.size()
    }

    /// Its device image, made (zeroed) if the diagram never synchronised it.
    pub fn device(&mut self, gpu: &Gpu) -> Result<&DeviceImage, String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!("the image container `{}` has no size yet (call create(width, height))", self.label));
        }
        if self.device.is_none() {
            let size = [self.width, self.height, 1];
            let image = DeviceImage::new(gpu, &self.label, self.format()?, 2, size).map_err(|e| e.to_string())?;
            self.device = Some(image);
        }
        Ok(self.device.as_ref().expect("made above"))
    }
}

impl BufferContainer {
    /// Its device buffer, made (zeroed) if the diagram never synchronised it.
    pub fn device(&mut self, gpu: &Gpu) -> Result<&DeviceBuffer, String> {
        if self.len == 0 {
            return Err(format!("the buffer container `{}` has no size yet (call create(width, height))", self.label));
        }
        if self.device.is_none() {
            let buffer = DeviceBuffer::new(gpu, &self.label, self.len * self.element.size() as u64)
                .map_err(|e| e.to_string())?;
            self.device = Some(buffer);
        }
        Ok(self.device.as_ref().expect("made above"))
    }
}
