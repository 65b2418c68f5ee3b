//! The C++ framework of the bundled library (`Framework.*`, Sec. 10.3.1) as the host interpreter
//! runs it: Qt's `QImage` (PNG and JPEG through the `image` crate), the viewer `Viewer2D`
//! (every image it is given is written as a PNG file when the run ends), the heterogeneous
//! computing containers `ImageContainer<T>` and `BufferContainer<T>` (a host copy and device
//! memory on the runtime's wgpu device, synchronised when the diagram says so), `HCDevicePtr`,
//! and the C functions of `CPPMethods` (`memcpy`, `rand`, `srand`, `time`, `printf`).

use std::{cell::RefCell, path::PathBuf, rc::Rc};

use gudsl_runtime::Gpu;

use gudsl_formats::picture;

use crate::{access::ModelFiles, output::OutputDir};

use super::value::{memory, BufferContainer, ImageContainer, Object, Pointer, QImage, Scalar, Shown, Value, Viewer};

/// `HCImageChannelOrder`'s constants, in the library's order.
const CHANNEL_ORDERS: [&str; 4] = ["R", "RGB", "RGBA", "BGRA"];
/// `QImageFormat::Format_RGB32`: opaque pixels.
const FORMAT_RGB32: i32 = 0;
/// OpenGL's `GL_UNSIGNED_BYTE`, the only pixel type the viewer shows.
const GL_UNSIGNED_BYTE: i32 = 5121;

/// A method or function of the framework.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    NewImage,
    Load,
    ConvertToFormat,
    Width,
    Height,
    ScanLine,
    NewViewer,
    AddImageObject,
    SetImage,
    SetImageData,
    Show,
    Resize,
    NewImageContainer(Scalar),
    NewBufferContainer(Scalar),
    Create,
    Fill,
    SyncToGpu,
    SyncToCpu,
    HostPointer,
    NumberOfElements,
    Device,
    MaxWorkGroupSize,
    Memcpy,
    Srand,
    Time,
    Rand,
    Printf,
}

impl Method {
    /// The method `name` of the framework class `class` (simple name) taking `args` arguments.
    pub fn resolve(class: &str, name: &str, args: usize) -> Option<Method> {
        use Method::*;
        Some(match (class, name, args) {
            ("QImage", "load", 1) => Load,
            ("QImage", "convertToFormat", 1) => ConvertToFormat,
            ("QImage" | "ImageContainer", "width", 0) => Width,
            ("QImage" | "ImageContainer", "height", 0) => Height,
            ("QImage", "scanLine", 1) => ScanLine,
            ("Viewer2D", "addImageObject", 3) => AddImageObject,
            ("Viewer2D", "setImage", 3) => SetImage,
            ("Viewer2D", "setImage", 9) => SetImageData,
            ("Viewer2D", "show", 0) => Show,
            ("Viewer2D", "resize", 2) => Resize,
            ("ImageContainer" | "BufferContainer", "create", 2) => Create,
            ("ImageContainer" | "BufferContainer", "fill", 1) => Fill,
            ("ImageContainer" | "BufferContainer", "syncToGPU", 0) => SyncToGpu,
            ("ImageContainer" | "BufferContainer", "syncToCPU", 0) => SyncToCpu,
            ("ImageContainer" | "BufferContainer", "hostPointer", 0) => HostPointer,
            ("ImageContainer", "numberOfElements", 0) => NumberOfElements,
            ("ImageContainer" | "BufferContainer", "device", 0) => Device,
            ("HCDevicePtr", "getMaxDeviceWorkGroupSize", 0) => MaxWorkGroupSize,
            ("CPPMethods", "memcpy", 3) => Memcpy,
            ("CPPMethods", "srand", 1) => Srand,
            ("CPPMethods", "time", 1) => Time,
            ("CPPMethods", "rand", 0) => Rand,
            ("CPPMethods", "printf", _) => Printf,
            _ => return None,
        })
    }

    /// `new class<element>(…)` of a framework class.
    pub fn constructor(class: &str, element: Option<Scalar>) -> Option<Method> {
        Some(match class {
            "QImage" => Method::NewImage,
            "Viewer2D" => Method::NewViewer,
            "ImageContainer" => Method::NewImageContainer(element?),
            "BufferContainer" => Method::NewBufferContainer(element?),
            _ => return None,
        })
    }
}

/// What the framework's calls need from the run: the device, the folder relative file names
/// are read from, `rand`'s state, the viewers made so far and what was printed.
pub struct Framework<'g> {
    pub gpu: &'g Gpu,
    pub files: ModelFiles,
    /// `rand`'s state (native loops step it in place: `native/emit.rs`'s `rand`).
    pub rand_state: u32,
    pub viewers: Vec<Rc<RefCell<Object>>>,
    pub printed: Vec<String>,
}

impl<'g> Framework<'g> {
    pub fn new(gpu: &'g Gpu, files: ModelFiles) -> Framework<'g> {
        Framework { gpu, files, rand_state: 1, viewers: Vec::new(), printed: Vec::new() }
    }

    /// `rand()`: xorshift32, so that `RAND_MAX` is 2^31 − 1 as glibc's (native loops compute
    /// the same steps inline).
    #[inline]
    pub fn rand(&mut self) -> i32 {
        let mut x = self.rand_state;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.rand_state = x;
        (x >> 1) as i32
    }

    /// Calls `method` with `args` (the receiver first for a method).
    pub fn call(&mut self, method: Method, args: &[Value]) -> Result<Value, String> {
        use Method::*;
        let int = |i: usize| int_arg(args, i);
        match method {
            NewImage => Ok(object(Object::Image(QImage { width: 0, height: 0, pixels: memory(0) }))),
            NewViewer => {
                let viewer = Rc::new(RefCell::new(Object::Viewer(Viewer {
                    number: self.viewers.len() + 1,
                    images: Vec::new(),
                })));
                self.viewers.push(viewer.clone());
                Ok(Value::Object(viewer))
            }
            NewImageContainer(element) => {
                let label = string_arg(args, 0).unwrap_or_else(|_| "image".into());
                if let Some(order) = args.get(1) {
                    let order = order.number().map(|n| n.as_i64()).unwrap_or(-1);
                    if !matches!(CHANNEL_ORDERS.get(order as usize), Some(&"RGBA")) {
                        let name = CHANNEL_ORDERS.get(order as usize).unwrap_or(&"?");
                        return Err(format!("channel order {name}: device images are RGBA (four channels per texel)"));
                    }
                }
                let container = ImageContainer { label, element, width: 0, height: 0, host: memory(0), device: None };
                Ok(object(Object::Images(container)))
            }
            NewBufferContainer(element) => {
                let label = string_arg(args, 0).unwrap_or_else(|_| "buffer".into());
                Ok(object(Object::Buffer(BufferContainer { label, element, len: 0, host: memory(0), device: None })))
            }
            Memcpy => {
                let (dst, src, bytes) = (pointer_arg(args, 0)?, pointer_arg(args, 1)?, int(2)?);
                let bytes = usize::try_from(bytes).map_err(|_| format!("memcpy of {bytes} bytes"))?;
                dst.put(&src.bytes(bytes)?)?;
                Ok(Value::Void)
            }
            Srand => {
                self.rand_state = (int(0)? as u32).max(1);
                Ok(Value::Void)
            }
            Time => {
                let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
                Ok(Value::Int(now.as_secs() as i32))
            }
            Rand => Ok(Value::Int(self.rand())),
            Printf => {
                let format = string_arg(args, 0)?;
                let text = super::printf::format(&format, &args[1..])?;
                self.printed.push(text.clone());
                Ok(Value::Str(text.into()))
            }
            _ => {
                let Some(Value::Object(receiver)) = args.first() else {
                    let what = args.first().map_or("nothing", Value::kind);
                    return Err(format!("{method:?} is called on {what}"));
                };
                let receiver = receiver.clone();
                let mut object = receiver.borrow_mut();
                self.method(method, &mut object, &args[1..])
            }
        }
    }

    /// `method` of `receiver`, by the receiver's class.
    fn method(&mut self, method: Method, receiver: &mut Object, args: &[Value]) -> Result<Value, String> {
        match receiver {
            Object::Image(image) => self.image_method(method, image, args),
            Object::Viewer(viewer) => viewer_method(method, viewer, args),
            Object::Images(_) | Object::Buffer(_) => self.container_method(method, receiver, args),
            Object::Device { max_work_group_size } => match method {
                Method::MaxWorkGroupSize => Ok(Value::Int(*max_work_group_size as i32)),
                _ => Err(not_a_method(method, "HCDevicePtr")),
            },
        }
    }

    /// A method of a `QImage`.
    fn image_method(&mut self, method: Method, image: &mut QImage, args: &[Value]) -> Result<Value, String> {
        let int = |i: usize| int_arg(args, i);
        match method {
            Method::Load => {
                *image = load_image(&self.files, &string_arg(args, 0)?)?;
                Ok(Value::Bool(true))
            }
            Method::ConvertToFormat => {
                let bytes = image.pixels.borrow().clone();
                let converted =
                    QImage { width: image.width, height: image.height, pixels: Rc::new(RefCell::new(bytes)) };
                if int(0)? == FORMAT_RGB32 as i64 {
                    converted.pixels.borrow_mut().iter_mut().skip(3).step_by(4).for_each(|alpha| *alpha = 255);
                }
                Ok(object(Object::Image(converted)))
            }
            Method::Width => Ok(Value::Int(image.width as i32)),
            Method::Height => Ok(Value::Int(image.height as i32)),
            Method::ScanLine => {
                let line = int(0)?;
                if line < 0 || line >= image.height as i64 {
                    return Err(format!("scan line {line} of an image {} lines high", image.height));
                }
                Ok(Value::Ptr(Pointer::to(image.pixels.clone(), Scalar::U8).add(line * 4 * image.width as i64)))
            }
            _ => Err(not_a_method(method, "QImage")),
        }
    }

    /// A method of an `ImageContainer` or a `BufferContainer` (`container`).
    fn container_method(&mut self, method: Method, container: &mut Object, args: &[Value]) -> Result<Value, String> {
        let int = |i: usize| int_arg(args, i);
        let gpu = self.gpu;
        match (method, container) {
            (Method::Width, Object::Images(images)) => Ok(Value::Int(images.width as i32)),
            (Method::Height, Object::Images(images)) => Ok(Value::Int(images.height as i32)),
            (Method::Create, Object::Images(images)) => {
                let (width, height) = (int(0)?, int(1)?);
                if width <= 0 || height <= 0 || width > u32::MAX as i64 || height > u32::MAX as i64 {
                    return Err(format!("an image of {width}×{height} pixels"));
                }
                images.width = width as u32;
                images.height = height as u32;
                images.host = memory(images.bytes());
                images.device = None;
                Ok(Value::Void)
            }
            (Method::Create, Object::Buffer(buffer)) => {
                let (width, height) = (int(0)?, int(1)?);
                if width <= 0 || height <= 0 {
                    return Err(format!("a buffer of {width}×{height} elements"));
                }
                buffer.len = (width * height) as u64;
                buffer.host = memory(buffer.len as usize * buffer.element.size());
                buffer.device = None;
                Ok(Value::Void)
            }
            (Method::Fill, container) => {
                let host = container.host().expect("a container");
                let len = host.memory.borrow().len();
                host.put(&pointer_arg(args, 0)?.bytes(len)?)?;
                Ok(Value::Void)
            }
            (Method::SyncToGpu, Object::Images(images)) => {
                let host = images.host.clone();
                images.device(gpu)?.write(gpu, &host.borrow()).map_err(|e| e.to_string())?;
                Ok(Value::Void)
            }
            (Method::SyncToGpu, Object::Buffer(buffer)) => {
                let host = buffer.host.clone();
                buffer.device(gpu)?.write(gpu, &host.borrow()).map_err(|e| e.to_string())?;
                Ok(Value::Void)
            }
            (Method::SyncToCpu, Object::Images(images)) => {
                let bytes = images.device(gpu)?.read(gpu).map_err(|e| e.to_string())?;
                images.host.borrow_mut().copy_from_slice(&bytes);
                Ok(Value::Void)
            }
            (Method::SyncToCpu, Object::Buffer(buffer)) => {
                let bytes = buffer.device(gpu)?.read(gpu).map_err(|e| e.to_string())?;
                buffer.host.borrow_mut().copy_from_slice(&bytes);
                Ok(Value::Void)
            }
            (Method::HostPointer, container) => Ok(Value::Ptr(container.host().expect("a container"))),
            (Method::NumberOfElements, Object::Images(images)) => Ok(Value::Int((images.width * images.height) as i32)),
            (Method::Device, _) => {
                let limits = gpu.device.limits();
                let size = limits.max_compute_invocations_per_workgroup.min(limits.max_compute_workgroup_size_x);
                Ok(object(Object::Device { max_work_group_size: size }))
            }
            (method, container) => Err(not_a_method(method, container.class())),
        }
    }

    /// Writes every viewer's images into `folder` as `viewer<n>-image<i>.png`; the paths.
    pub fn write_viewers(&self, output: &mut OutputDir) -> Result<Vec<PathBuf>, String> {
        let mut written = Vec::new();
        for viewer in &self.viewers {
            let Object::Viewer(viewer) = &*viewer.borrow() else { continue };
            for (index, shown) in viewer.images.iter().enumerate() {
                let Some(shown) = shown else { continue };
                let name = format!("viewer{}-image{index}.png", viewer.number);
                let png = shown.png().map_err(|e| format!("{name}: {e}"))?;
                written.push(output.write_top(&name, &png)?);
            }
        }
        Ok(written)
    }
}

impl Viewer {
    fn set(&mut self, index: i64, shown: Shown) -> Result<Value, String> {
        let count = self.images.len();
        let slot = usize::try_from(index)
            .ok()
            .and_then(|i| self.images.get_mut(i))
            .ok_or_else(|| format!("image object {index}: the viewer has {count} (addImageObject adds them)"))?;
        *slot = Some(shown);
        Ok(Value::Void)
    }
}

impl Shown {
    /// As an opaque PNG (a viewer draws no transparency): RGB, or grey for one channel.
    fn png(&self) -> Result<Vec<u8>, image::ImageError> {
        let (bytes, color): (Vec<u8>, image::ExtendedColorType) = match self.channels {
            1 => (self.bytes.clone(), image::ExtendedColorType::L8),
            3 => (self.bytes.clone(), image::ExtendedColorType::Rgb8),
            _ => {
                (self.bytes.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect(), image::ExtendedColorType::Rgb8)
            }
        };
        let mut png = Vec::new();
        image::write_buffer_with_format(
            &mut std::io::Cursor::new(&mut png),
            &bytes,
            self.width,
            self.height,
            color,
            image::ImageFormat::Png,
        )?;
        Ok(png)
    }
}

/// `QImage::load`: a PNG or JPEG file, relative to the folder of the diagram's file.
fn load_image(files: &ModelFiles, name: &str) -> Result<QImage, String> {
    let path = files.path(name);
    let folder = files.folder(&path).map_err(|e| format!("cannot read the image {e}"))?;
    let decoded = picture::decode(folder, &path).map_err(|e| format!("cannot read the image {e}"))?;
    let rgba = decoded.to_rgba8();
    let (width, height) = rgba.dimensions();
    Ok(QImage { width, height, pixels: Rc::new(RefCell::new(rgba.into_raw())) })
}

fn object(object: Object) -> Value {
    Value::Object(Rc::new(RefCell::new(object)))
}

fn int_arg(args: &[Value], i: usize) -> Result<i64, String> {
    match args.get(i).and_then(Value::number) {
        Some(number) => Ok(number.as_i64()),
        None => Err(format!("argument {} is not a number", i + 1)),
    }
}

fn string_arg(args: &[Value], i: usize) -> Result<String, String> {
    match args.get(i) {
        Some(Value::Str(s)) => Ok(s.to_string()),
        other => Err(format!("argument {} is a {}, not a string", i + 1, other.map_or("nothing", Value::kind))),
    }
}

fn pointer_arg(args: &[Value], i: usize) -> Result<Pointer, String> {
    match args.get(i) {
        Some(Value::Ptr(p)) => Ok(p.clone()),
        Some(Value::Null) => Err(format!("argument {} is null", i + 1)),
        other => Err(format!("argument {} is a {}, not a pointer", i + 1, other.map_or("nothing", Value::kind))),
    }
}

/// A method of a `Viewer2D`.
fn viewer_method(method: Method, viewer: &mut Viewer, args: &[Value]) -> Result<Value, String> {
    let int = |i: usize| int_arg(args, i);
    match method {
        Method::AddImageObject => {
            viewer.images.push(None);
            Ok(Value::Int(viewer.images.len() as i32 - 1))
        }
        Method::SetImage => {
            let Some(Value::Object(image)) = args.first() else {
                return Err("setImage(image, index, copy) is given no image".into());
            };
            let Object::Image(image) = &*image.borrow() else { return Err("setImage is given no QImage".into()) };
            let shown =
                Shown { width: image.width, height: image.height, channels: 4, bytes: image.pixels.borrow().clone() };
            viewer.set(int(1)?, shown)
        }
        Method::SetImageData => {
            let (data, size, width, height, format) = (pointer_arg(args, 0)?, int(1)?, int(3)?, int(4)?, int(5)?);
            if format != GL_UNSIGNED_BYTE as i64 {
                return Err(format!(
                    "pixel type {format}: the viewer shows GL_UNSIGNED_BYTE ({GL_UNSIGNED_BYTE}) data"
                ));
            }
            let pixels = width.max(0) * height.max(0);
            if pixels == 0 || size <= 0 || size % pixels != 0 || !matches!(size / pixels, 1 | 3 | 4) {
                return Err(format!("{size} bytes for a {width}×{height} image: 1, 3 or 4 bytes a pixel are shown"));
            }
            let bytes = data.bytes(size as usize)?;
            let shown = Shown { width: width as u32, height: height as u32, channels: (size / pixels) as u8, bytes };
            viewer.set(int(6)?, shown)
        }
        Method::Show | Method::Resize => Ok(Value::Void),
        _ => Err(not_a_method(method, "Viewer2D")),
    }
}

/// Why `method` cannot be called on an object of `class`.
fn not_a_method(method: Method, class: &str) -> String {
    format!("{method:?} is not a method of {class}")
}
