//! Numeric arrays in NumPy's files, read and written through `npyz` (and `zip` for archives):
//! `.npy` files of every numeric dtype (booleans, signed and unsigned integers, float16/32/64),
//! either byte order, C or Fortran order, and single arrays of `.npz` archives (stored or
//! deflated, as `np.savez` and `np.savez_compressed` write them). Values come as f32 in C order,
//! with the dtype they had, so a caller can refuse the wrong one by name.

use std::{
    fmt, fs,
    io::{self, Read},
    path::{Path, PathBuf},
};

use gudsl_files::Folder;
use npyz::{DType, NpyFile, Order, TypeChar, WriterBuilder};

/// An array: its shape, its values in C order, and the element type of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Array {
    pub shape: Vec<usize>,
    pub values: Vec<f32>,
    pub dtype: Dtype,
}

/// The element type of an array in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dtype {
    pub kind: Kind,
    /// Bytes per element.
    pub bytes: usize,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Bool,
    Int,
    Uint,
    Float,
}

impl Dtype {
    pub const U16: Dtype = Dtype { kind: Kind::Uint, bytes: 2 };
    pub const F32: Dtype = Dtype { kind: Kind::Float, bytes: 4 };

    /// Whether its values are whole numbers (booleans and integers).
    pub fn is_integer(self) -> bool {
        self.kind != Kind::Float
    }
}

/// NumPy's name: `uint16`, `float32`, `bool`.
impl fmt::Display for Dtype {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            Kind::Bool => f.write_str("bool"),
            Kind::Int => write!(f, "int{}", self.bytes * 8),
            Kind::Uint => write!(f, "uint{}", self.bytes * 8),
            Kind::Float => write!(f, "float{}", self.bytes * 8),
        }
    }
}

/// Why an array cannot be read or written, naming the file.
#[derive(Debug)]
pub struct ArrayError {
    pub path: PathBuf,
    pub kind: io::ErrorKind,
    pub message: String,
}

impl fmt::Display for ArrayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for ArrayError {}

impl ArrayError {
    pub(crate) fn new(path: &Path, kind: io::ErrorKind, message: impl Into<String>) -> ArrayError {
        ArrayError { path: path.to_path_buf(), kind, message: message.into() }
    }

    pub(crate) fn io(path: &Path, error: io::Error) -> ArrayError {
        let message = match error.kind() {
            io::ErrorKind::NotFound => "does not exist".to_string(),
            io::ErrorKind::UnexpectedEof => "is truncated: it holds fewer values than its shape says".to_string(),
            _ => error.to_string(),
        };
        ArrayError::new(path, error.kind(), message)
    }

    /// A file its folder refused to open (missing, outside, not a regular file, too long).
    fn file(error: gudsl_files::FileError) -> ArrayError {
        let kind = match error.problem {
            gudsl_files::Problem::NotFound => io::ErrorKind::NotFound,
            _ => io::ErrorKind::InvalidInput,
        };
        ArrayError::new(&error.path, kind, error.problem.to_string())
    }

    pub(crate) fn invalid(path: &Path, message: impl Into<String>) -> ArrayError {
        ArrayError::new(path, io::ErrorKind::InvalidData, message)
    }
}

/// Where an array is: a `.npy` file, or `archive.npz:name` (`archive.npz` alone: its only
/// array).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Source {
    pub file: PathBuf,
    pub member: Option<String>,
}

impl Source {
    pub fn parse(path: &Path) -> Source {
        let text = path.to_string_lossy();
        match text.rsplit_once(".npz:") {
            Some((archive, member)) if !member.contains(['/', '\\']) => {
                Source { file: PathBuf::from(format!("{archive}.npz")), member: Some(member.to_string()) }
            }
            _ => Source { file: path.to_path_buf(), member: None },
        }
    }

    fn is_archive(&self) -> bool {
        self.member.is_some() || self.file.extension().is_some_and(|e| e.eq_ignore_ascii_case("npz"))
    }
}

/// The shape and element type of the array at `path` (a `.npy` file or `archive.npz[:name]`
/// beneath `folder`), read from its header only.
pub fn header(folder: &Folder, path: &Path) -> Result<(Vec<usize>, Dtype), ArrayError> {
    with_array(folder, path, |file, path| Ok((shape_of(&file), dtype_of(&file, path)?)))
}

/// The array at `path` (a `.npy` file or `archive.npz[:name]` beneath `folder`).
pub fn read(folder: &Folder, path: &Path) -> Result<Array, ArrayError> {
    with_array(folder, path, array_of)
}

/// The array in `bytes`, read as the file `path` would be (`.npy`, or `archive.npz[:name]`):
/// what the fuzz target feeds, with no file in between.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<Array, ArrayError> {
    with_stream(io::Cursor::new(bytes), bytes.len() as u64, &Source::parse(path), array_of)
}

/// The values of an array whose header `file` has read, in C order.
fn array_of(file: NpyFile<&mut dyn Read>, path: &Path) -> Result<Array, ArrayError> {
    let shape = shape_of(&file);
    let dtype = dtype_of(&file, path)?;
    let fortran = file.order() == Order::Fortran;
    let values = values(file, dtype).map_err(|e| ArrayError::io(path, e))?;
    let values = if fortran { to_c_order(&values, &shape) } else { values };
    Ok(Array { shape, values, dtype })
}

/// Opens the array at `path` beneath `folder` (a regular file of at most [`MAX_ARRAY_BYTES`])
/// and hands its reader (positioned after the header) to `f`.
pub(crate) fn with_array<T>(
    folder: &Folder,
    path: &Path,
    f: impl FnOnce(NpyFile<&mut dyn Read>, &Path) -> Result<T, ArrayError>,
) -> Result<T, ArrayError> {
    let source = Source::parse(path);
    let opened = folder.open_file(&source.file, MAX_ARRAY_BYTES).map_err(ArrayError::file)?;
    with_stream(opened.file, opened.len, &source, f)
}

/// The array `source` names in `stream` (`length` bytes: a `.npy` file or a `.npz` archive),
/// its reader (positioned after the header) handed to `f`.
fn with_stream<T>(
    mut stream: impl Read + io::Seek,
    length: u64,
    source: &Source,
    f: impl FnOnce(NpyFile<&mut dyn Read>, &Path) -> Result<T, ArrayError>,
) -> Result<T, ArrayError> {
    if !source.is_archive() {
        let mut reader = io::BufReader::new(&mut stream);
        let header = header_checked(&mut reader, &source.file)?;
        let mut reader = io::Cursor::new(header).chain(reader);
        let npy = NpyFile::new(&mut reader as &mut dyn Read).map_err(|e| not_npy(&source.file, e))?;
        claims_what_it_holds(&npy, &source.file, length)?;
        return f(npy, &source.file);
    }
    let mut archive = zip::ZipArchive::new(io::BufReader::new(stream))
        .map_err(|e| ArrayError::invalid(&source.file, format!("is not a .npz archive ({e})")))?;
    let names: Vec<String> = archive.file_names().filter_map(|n| n.strip_suffix(".npy")).map(str::to_string).collect();
    let member = match (&source.member, &names[..]) {
        (Some(member), _) => member.clone(),
        (None, [only]) => only.clone(),
        (None, _) => {
            return Err(ArrayError::invalid(
                &source.file,
                format!(
                    "holds {} arrays ({}): name one as `{}:NAME`",
                    names.len(),
                    names.join(", "),
                    source.file.display()
                ),
            ))
        }
    };
    let mut entry = match archive.by_name(&format!("{member}.npy")) {
        Ok(entry) => entry,
        Err(_) => {
            return Err(ArrayError::new(
                &source.file,
                io::ErrorKind::NotFound,
                format!("has no array `{member}` (it holds {})", names.join(", ")),
            ))
        }
    };
    let shown = PathBuf::from(format!("{}:{member}", source.file.display()));
    let length = entry.size();
    let header = header_checked(&mut entry, &shown)?;
    let mut entry = io::Cursor::new(header).chain(entry);
    let npy = NpyFile::new(&mut entry as &mut dyn Read).map_err(|e| not_npy(&shown, e))?;
    claims_what_it_holds(&npy, &shown, length)?;
    f(npy, &shown)
}

/// The header of a `.npy` stream, read before any parser sees it: its bytes (handed on to the
/// parser), refused where its shape's dimensions (at up to 16 bytes a value) make more bytes
/// than exist, which a parser would overflow computing.
fn header_checked(reader: &mut impl Read, path: &Path) -> Result<Vec<u8>, ArrayError> {
    let malformed = |why: &str| not_npy(path, io::Error::new(io::ErrorKind::InvalidData, why.to_string()));
    let mut bytes = vec![0u8; 8];
    reader.read_exact(&mut bytes).map_err(|e| not_npy(path, e))?;
    if &bytes[..6] != b"\x93NUMPY" {
        return Err(malformed("no NumPy header"));
    }
    let width = if bytes[6] == 1 { 2 } else { 4 };
    let mut length = vec![0u8; width];
    reader.read_exact(&mut length).map_err(|e| not_npy(path, e))?;
    let length = length.iter().rev().fold(0usize, |n, &b| n << 8 | b as usize);
    if length > 1 << 20 {
        return Err(malformed("a header of more than 1 MiB"));
    }
    let mut text = vec![0u8; length];
    reader.read_exact(&mut text).map_err(|e| not_npy(path, e))?;
    // NumPy writes a flat dict holding one tuple; deeper nesting sends the header parser into
    // exponential backtracking (a 160-byte header of `{{{{…` took 92 s): refused unparsed.
    if nesting(&text) > 2 {
        return Err(malformed("a header nested deeper than NumPy writes (a dict holding a tuple)"));
    }
    let dims: Vec<String> = String::from_utf8_lossy(&text)
        .split("'shape':")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .map(|tuple| tuple.trim_start().trim_start_matches('(').split(',').map(|d| d.trim().to_string()).collect())
        .unwrap_or_default();
    let fits = dims.iter().filter(|d| !d.is_empty()).try_fold(16u64, |n, d| n.checked_mul(d.parse::<u64>().ok()?));
    if fits.is_none() {
        let shape = dims.iter().filter(|d| !d.is_empty()).cloned().collect::<Vec<_>>().join(", ");
        return Err(ArrayError::invalid(path, format!("has shape ({shape}): more values than can exist")));
    }
    bytes.extend((length as u64).to_le_bytes().iter().take(width));
    bytes.extend(text);
    Ok(bytes)
}

/// How deeply the brackets of a header nest (`{'shape': (2, 3)}`: 2); unbalanced closers count
/// as nothing.
fn nesting(text: &[u8]) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for &byte in text {
        match byte {
            b'(' | b'[' | b'{' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

/// The most bytes of values an array may hold (4 GiB): a header claiming more is refused before
/// anything is allocated.
pub const MAX_ARRAY_BYTES: u64 = 1 << 32;

/// An error unless the header's shape and element size make a number of bytes that exists and
/// that the file (`length` bytes, its header included) can hold, up to [`MAX_ARRAY_BYTES`]: a
/// header is never trusted to size an allocation.
fn claims_what_it_holds<R: Read>(file: &NpyFile<R>, path: &Path, length: u64) -> Result<(), ArrayError> {
    let shape = file.shape();
    let element = file.dtype().num_bytes().map_or(1, |b| b as u64);
    let needed = shape.iter().try_fold(element, |bytes, &dim| bytes.checked_mul(dim));
    let shape_text = || format!("({})", shape.iter().map(u64::to_string).collect::<Vec<_>>().join(", "));
    match needed {
        None => Err(ArrayError::invalid(path, format!("has shape {}: more values than can exist", shape_text()))),
        Some(needed) if needed > length => Err(ArrayError::invalid(
            path,
            format!("has shape {} ({needed} bytes of values), but holds only {length} bytes", shape_text()),
        )),
        Some(needed) if needed > MAX_ARRAY_BYTES => Err(ArrayError::invalid(
            path,
            format!("has shape {} ({needed} bytes), more than the {MAX_ARRAY_BYTES} bytes read", shape_text()),
        )),
        Some(_) => Ok(()),
    }
}

fn not_npy(path: &Path, error: io::Error) -> ArrayError {
    ArrayError::invalid(path, format!("is not a NumPy array file ({error})"))
}

pub(crate) fn shape_of<R: Read>(file: &NpyFile<R>) -> Vec<usize> {
    file.shape().iter().map(|&d| d as usize).collect()
}

pub(crate) fn dtype_of<R: Read>(file: &NpyFile<R>, path: &Path) -> Result<Dtype, ArrayError> {
    let unsupported =
        || ArrayError::invalid(path, format!("has dtype {}: not a number", file.dtype().descr().trim_matches('\'')));
    let DType::Plain(ty) = file.dtype() else { return Err(unsupported()) };
    let kind = match ty.type_char() {
        TypeChar::Bool => Kind::Bool,
        TypeChar::Int => Kind::Int,
        TypeChar::Uint => Kind::Uint,
        TypeChar::Float => Kind::Float,
        _ => return Err(unsupported()),
    };
    let bytes = ty.size_field() as usize;
    match (kind, bytes) {
        (Kind::Bool, 1) | (Kind::Int | Kind::Uint, 1 | 2 | 4 | 8) | (Kind::Float, 2 | 4 | 8) => {
            Ok(Dtype { kind, bytes })
        }
        _ => Err(unsupported()),
    }
}

/// How the bytes of one value of a little-endian (or one-byte) `u8`, `u16` or `f32` array
/// convert: what cameras record, read a chunk of bytes at a time instead of value by value
/// (about 10× faster for a frame).
fn bulk<R: Read>(file: &NpyFile<R>, dtype: Dtype) -> Option<fn(&[u8]) -> f32> {
    let DType::Plain(ty) = file.dtype() else { return None };
    if ty.endianness() == npyz::Endianness::Big && dtype.bytes > 1 {
        return None;
    }
    match (dtype.kind, dtype.bytes) {
        (Kind::Uint, 1) => Some(|b| f32::from(b[0])),
        (Kind::Uint, 2) => Some(|b| f32::from(u16::from_le_bytes([b[0], b[1]]))),
        (Kind::Float, 4) => Some(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// [`chunks_of`] for the dtypes [`bulk`] converts: each chunk's bytes read at once.
fn bulk_chunks<R: Read>(
    file: NpyFile<R>,
    bytes: usize,
    convert: fn(&[u8]) -> f32,
    chunk: usize,
    sink: &mut dyn FnMut(Vec<f32>) -> bool,
) -> io::Result<()> {
    let mut left = file.shape().iter().product::<u64>() as usize;
    let mut reader = file.into_inner();
    // Bytes read a block at a time: a chunk of `usize::MAX` values (the whole array) is not
    // allocated before the file shows it holds them.
    let mut raw = vec![0u8; (chunk.min(left).min(1 << 20)) * bytes];
    while left > 0 {
        let size = chunk.min(left);
        let mut out = Vec::with_capacity(size.min(1 << 24));
        let mut wanted = size;
        while wanted > 0 {
            let block = wanted.min(raw.len() / bytes);
            let buffer = &mut raw[..block * bytes];
            reader.read_exact(buffer)?;
            out.extend(buffer.chunks_exact(bytes).map(convert));
            wanted -= block;
        }
        left -= size;
        if !sink(out) {
            break;
        }
    }
    Ok(())
}

/// The values as f32 (integers beyond 2^24 round).
pub(crate) fn values<R: Read>(file: NpyFile<R>, dtype: Dtype) -> io::Result<Vec<f32>> {
    let mut all = Vec::new();
    chunks_of(file, dtype, usize::MAX, &mut |chunk| {
        all = chunk;
        false
    })?;
    Ok(all)
}

/// The values of `file` in chunks of `chunk` (the last may be shorter), each handed to `sink`
/// as it is read; stops when `sink` says so (returns `false`). Memory: one chunk.
pub(crate) fn chunks_of<R: Read>(
    file: NpyFile<R>,
    dtype: Dtype,
    chunk: usize,
    sink: &mut dyn FnMut(Vec<f32>) -> bool,
) -> io::Result<()> {
    fn typed<T: npyz::Deserialize, R: Read>(
        file: NpyFile<R>,
        to: impl Fn(T) -> f32,
        chunk: usize,
        sink: &mut dyn FnMut(Vec<f32>) -> bool,
    ) -> io::Result<()> {
        let total = file.shape().iter().product::<u64>() as usize;
        let mut values = file.data::<T>().map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))?;
        let mut left = total;
        while left > 0 {
            let size = chunk.min(left);
            let mut out = Vec::with_capacity(size);
            for value in values.by_ref().take(size) {
                out.push(to(value?));
            }
            left -= size;
            if !sink(out) {
                break;
            }
        }
        Ok(())
    }
    if let Some(convert) = bulk(&file, dtype) {
        return bulk_chunks(file, dtype.bytes, convert, chunk, sink);
    }
    match (dtype.kind, dtype.bytes) {
        (Kind::Bool, _) => typed(file, |v: bool| f32::from(u8::from(v)), chunk, sink),
        (Kind::Int, 1) => typed(file, |v: i8| v as f32, chunk, sink),
        (Kind::Int, 2) => typed(file, |v: i16| v as f32, chunk, sink),
        (Kind::Int, 4) => typed(file, |v: i32| v as f32, chunk, sink),
        (Kind::Int, _) => typed(file, |v: i64| v as f32, chunk, sink),
        (Kind::Uint, 1) => typed(file, |v: u8| v as f32, chunk, sink),
        (Kind::Uint, 2) => typed(file, |v: u16| v as f32, chunk, sink),
        (Kind::Uint, 4) => typed(file, |v: u32| v as f32, chunk, sink),
        (Kind::Uint, _) => typed(file, |v: u64| v as f32, chunk, sink),
        (Kind::Float, 2) => typed(file, |v: npyz::half::f16| v.to_f32(), chunk, sink),
        (Kind::Float, 4) => typed(file, |v: f32| v, chunk, sink),
        (Kind::Float, _) => typed(file, |v: f64| v as f32, chunk, sink),
    }
}

/// Values stored in Fortran order (first index fastest) in C order (last index fastest).
pub(crate) fn to_c_order(values: &[f32], shape: &[usize]) -> Vec<f32> {
    let mut out = vec![0.0; values.len()];
    let mut index = vec![0usize; shape.len()];
    for value in out.iter_mut() {
        // `index` counts in C order; its Fortran offset is the stored position.
        let mut offset = 0;
        let mut stride = 1;
        for (i, &dim) in index.iter().zip(shape) {
            offset += i * stride;
            stride *= dim;
        }
        *value = values[offset];
        for (i, &dim) in index.iter_mut().zip(shape).rev() {
            *i += 1;
            if *i < dim {
                break;
            }
            *i = 0;
        }
    }
    out
}

/// `data` (row-major, `shape`) as the bytes of a `.npy` file of `dtype` (`U16` rounds and
/// clamps to 0..=65535; any other is written as float32).
pub fn encode(shape: &[usize], data: &[f32], dtype: Dtype) -> Vec<u8> {
    assert_eq!(shape.iter().product::<usize>(), data.len(), "shape and data disagree");
    let shape: Vec<u64> = shape.iter().map(|&d| d as u64).collect();
    let mut bytes = Vec::new();
    let written = if dtype == Dtype::U16 {
        let options = npyz::WriteOptions::<u16>::new().default_dtype().shape(&shape).writer(&mut bytes);
        options.begin_nd().and_then(|mut writer| {
            writer.extend(data.iter().map(|v| v.round().clamp(0.0, 65535.0) as u16))?;
            writer.finish()
        })
    } else {
        let options = npyz::WriteOptions::<f32>::new().default_dtype().shape(&shape).writer(&mut bytes);
        options.begin_nd().and_then(|mut writer| {
            writer.extend(data.iter().copied())?;
            writer.finish()
        })
    };
    written.expect("writing to memory cannot fail");
    bytes
}

/// Writes `data` (row-major, `shape`) as a `.npy` file of `dtype`.
pub fn write(path: &Path, shape: &[usize], data: &[f32], dtype: Dtype) -> Result<(), ArrayError> {
    fs::write(path, encode(shape, data, dtype)).map_err(|e| ArrayError::io(path, e))
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    /// The folder of a scratch file, as a run would read it.
    fn folder_of(path: &Path) -> Folder {
        Folder::open(path.parent().unwrap()).unwrap()
    }

    fn read(path: &Path) -> Result<Array, ArrayError> {
        super::read(&folder_of(&Source::parse(path).file), path)
    }

    fn header(path: &Path) -> Result<(Vec<usize>, Dtype), ArrayError> {
        super::header(&folder_of(&Source::parse(path).file), path)
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("gudsl-arrays-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A `.npy` file with a hand-written header and body, as NumPy writes it.
    fn raw_npy(descr: &str, fortran: bool, shape: &str, body: &[u8]) -> Vec<u8> {
        let mut header = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
            if fortran { "True" } else { "False" }
        );
        header.push_str(&" ".repeat(63 - (10 + header.len()) % 64));
        header.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend((header.len() as u16).to_le_bytes());
        bytes.extend(header.as_bytes());
        bytes.extend(body);
        bytes
    }

    #[test]
    fn round_trips_both_written_dtypes() {
        let path = scratch("round.npy");
        let data: Vec<f32> = (0..24).map(|i| i as f32 * 1.5).collect();
        write(&path, &[2, 3, 4], &data, Dtype::F32).unwrap();
        assert_eq!(read(&path).unwrap(), Array { shape: vec![2, 3, 4], values: data.clone(), dtype: Dtype::F32 });
        write(&path, &[24], &data, Dtype::U16).unwrap();
        let array = read(&path).unwrap();
        assert_eq!((array.shape, array.dtype), (vec![24], Dtype::U16));
        assert_eq!(array.values, data.iter().map(|v| v.round()).collect::<Vec<_>>());
        assert_eq!(header(&path).unwrap(), (vec![24], Dtype::U16));
    }

    #[test]
    fn reads_every_numeric_dtype_in_either_byte_order_and_fortran_order() {
        let path = scratch("dtypes.npy");
        let cases: Vec<(&str, Vec<u8>, &str)> = vec![
            ("|b1", vec![1, 0, 1, 1, 0, 1], "bool"),
            ("|i1", [1i8, -2, 3, -4, 5, -6].iter().map(|v| *v as u8).collect(), "int8"),
            (">u2", [1u16, 2, 3, 4, 5, 6].iter().flat_map(|v| v.to_be_bytes()).collect(), "uint16"),
            ("<i4", [1i32, -2, 3, -4, 5, -6].iter().flat_map(|v| v.to_le_bytes()).collect(), "int32"),
            (">i8", [1i64, -2, 3, -4, 5, -6].iter().flat_map(|v| v.to_be_bytes()).collect(), "int64"),
            ("<u8", [1u64, 2, 3, 4, 5, 6].iter().flat_map(|v| v.to_le_bytes()).collect(), "uint64"),
            (
                "<f2",
                [1.0f32, 2.5, -3.0, 4.0, 5.0, 6.0]
                    .iter()
                    .flat_map(|v| npyz::half::f16::from_f32(*v).to_le_bytes())
                    .collect(),
                "float16",
            ),
            (">f4", [1.0f32, 2.5, -3.0, 4.0, 5.0, 6.0].iter().flat_map(|v| v.to_be_bytes()).collect(), "float32"),
            ("<f8", [1.0f64, 2.5, -3.0, 4.0, 5.0, 6.0].iter().flat_map(|v| v.to_le_bytes()).collect(), "float64"),
        ];
        for (descr, body, name) in cases {
            fs::write(&path, raw_npy(descr, false, "(2, 3)", &body)).unwrap();
            let array = read(&path).unwrap();
            assert_eq!(array.shape, [2, 3], "{descr}");
            assert_eq!(array.dtype.to_string(), name, "{descr}");
            assert_eq!(array.values.len(), 6, "{descr}");
        }
        // Fortran order: [[1, 2, 3], [4, 5, 6]] is stored column by column.
        let body: Vec<u8> = [1u16, 4, 2, 5, 3, 6].iter().flat_map(|v| v.to_le_bytes()).collect();
        fs::write(&path, raw_npy("<u2", true, "(2, 3)", &body)).unwrap();
        assert_eq!(read(&path).unwrap().values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let body: Vec<u8> = (0u16..24).flat_map(|v| v.to_le_bytes()).collect();
        fs::write(&path, raw_npy("<u2", true, "(2, 3, 4)", &body)).unwrap();
        let values = read(&path).unwrap().values;
        // C index (i, j, k) = (1, 2, 3) is at 12 i + 4 j + k in C order, stored at i + 2 j + 6 k.
        let (i, j, k) = (1, 2, 3);
        assert_eq!(values[12 * i + 4 * j + k], (i + 2 * j + 6 * k) as f32);
    }

    #[test]
    fn reads_arrays_of_npz_archives() {
        let path = scratch("frames.npz");
        let mut zip = zip::ZipWriter::new(fs::File::create(&path).unwrap());
        let deflated = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        zip.start_file("a.npy", deflated).unwrap();
        zip.write_all(&encode(&[2], &[1.0, 2.0], Dtype::U16)).unwrap();
        zip.start_file("b.npy", zip::write::SimpleFileOptions::default()).unwrap();
        zip.write_all(&encode(&[3], &[3.0, 4.0, 5.0], Dtype::F32)).unwrap();
        zip.finish().unwrap();
        let member = |name: &str| PathBuf::from(format!("{}:{name}", path.display()));
        assert_eq!(read(&member("a")).unwrap().values, [1.0, 2.0]);
        assert_eq!(read(&member("b")).unwrap().values, [3.0, 4.0, 5.0]);
        let error = read(&member("c")).unwrap_err();
        assert!(error.message.contains("has no array `c` (it holds a, b)"), "{error}");
        let error = read(&path).unwrap_err();
        assert!(error.message.contains("holds 2 arrays (a, b): name one"), "{error}");
    }

    /// Issue 48, item 4: a header that claims more than its file holds is an error before
    /// anything is allocated, never a panic or an abort.
    #[test]
    fn a_header_is_never_trusted_to_size_an_allocation() {
        let path = scratch("lying.npy");
        // The shape's product overflows u64 (it panicked in the run before).
        fs::write(&path, raw_npy("<f4", false, "(4294967296, 4294967296, 16)", &[])).unwrap();
        for error in [header(&path).unwrap_err(), read(&path).unwrap_err()] {
            assert!(error.message.contains("more values than can exist"), "{error}");
        }
        // 2^64 values claimed by a 128-byte file (the allocation aborted the process before).
        fs::write(&path, raw_npy("<f4", false, "(4294967296, 4294967296, 1)", &[])).unwrap();
        assert!(header(&path).unwrap_err().message.contains("more values than can exist"));
        // 16 GiB of values claimed by a 128-byte file.
        fs::write(&path, raw_npy("<f4", false, "(65536, 65536, 1)", &[])).unwrap();
        for error in [header(&path).unwrap_err(), read(&path).unwrap_err()] {
            assert!(error.message.contains("(17179869184 bytes of values), but holds only 128 bytes"), "{error}");
        }
        // A file truly as large as its shape says is read.
        fs::write(&path, raw_npy("<f4", false, "(2, 2)", &[0; 16])).unwrap();
        assert_eq!(header(&path).unwrap().0, vec![2, 2]);
    }

    #[test]
    fn a_header_that_sends_the_parser_backtracking_is_refused_at_once() {
        // Found by the fuzz target `npy`: 160 bytes that took the header parser 92 s.
        let slow = include_bytes!("../../fuzz/corpus/npy/nested_braces_took_92_s.npy");
        let started = std::time::Instant::now();
        let error = read_bytes(slow, Path::new("slow.npy")).unwrap_err();
        assert!(error.message.contains("nested deeper than NumPy writes"), "{error}");
        assert!(started.elapsed().as_millis() < 100, "{:?}", started.elapsed());
    }

    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let path = scratch("bad.npy");
        let error = read(&scratch("nowhere.npy")).unwrap_err();
        assert_eq!(error.kind, io::ErrorKind::NotFound);
        assert!(error.to_string().ends_with("nowhere.npy: does not exist"), "{error}");
        fs::write(&path, b"not numpy at all").unwrap();
        assert!(read(&path).unwrap_err().message.contains("is not a NumPy array file"));
        let bytes = encode(&[4], &[1.0, 2.0, 3.0, 4.0], Dtype::F32);
        fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
        let error = read(&path).unwrap_err();
        assert!(error.message.contains("truncated"), "{error}");
        fs::write(&path, raw_npy("<c8", false, "(1,)", &[0; 8])).unwrap();
        let error = read(&path).unwrap_err();
        assert!(error.message.contains("has dtype <c8: not a number"), "{error}");
        fs::write(scratch("not.npz"), b"PK but not really").unwrap();
        assert!(read(&scratch("not.npz")).unwrap_err().message.contains("is not a .npz archive"));
    }
}
