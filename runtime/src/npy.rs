//! NumPy `.npy` files (format version 1.0, C order, little endian): raw frames as `<u2`, images
//! as `<f4`, so frames move between the runtime and NumPy, OpenCV or a camera recorder.

use std::{fs, io, path::Path};

/// Element types the runtime writes and reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dtype {
    U16,
    F32,
}

impl Dtype {
    fn descr(self) -> &'static str {
        match self {
            Dtype::U16 => "<u2",
            Dtype::F32 => "<f4",
        }
    }
}

/// Writes `data` (row-major, `shape`) as `dtype` (`U16` rounds and clamps to 0..=65535).
pub fn save(path: &Path, shape: &[usize], data: &[f32], dtype: Dtype) -> io::Result<()> {
    fs::write(path, encode(shape, data, dtype))
}

/// `data` (row-major, `shape`) as the bytes of a `.npy` file of `dtype`.
pub fn encode(shape: &[usize], data: &[f32], dtype: Dtype) -> Vec<u8> {
    assert_eq!(shape.iter().product::<usize>(), data.len(), "shape and data disagree");
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_text = if dims.len() == 1 { format!("({},)", dims[0]) } else { format!("({})", dims.join(", ")) };
    let mut header = format!("{{'descr': '{}', 'fortran_order': False, 'shape': {shape_text}, }}", dtype.descr());
    // Magic (6) + version (2) + length (2) + header + newline, padded to a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    match dtype {
        Dtype::U16 => bytes.extend(data.iter().flat_map(|v| (v.round().clamp(0.0, 65535.0) as u16).to_le_bytes())),
        Dtype::F32 => bytes.extend(data.iter().flat_map(|v| v.to_le_bytes())),
    }
    bytes
}

/// Reads a `<u2` or `<f4` array: its shape and its values as f32.
pub fn load(path: &Path) -> io::Result<(Vec<usize>, Vec<f32>)> {
    let bytes = fs::read(path)?;
    let invalid = |why: &str| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {why}", path.display()));
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err(invalid("not a .npy file"));
    }
    let (header_len, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 if bytes.len() >= 12 => (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12),
        _ => return Err(invalid("unsupported .npy version")),
    };
    let header = bytes.get(start..start + header_len).ok_or_else(|| invalid("truncated header"))?;
    let header = std::str::from_utf8(header).map_err(|_| invalid("header is not text"))?;
    let field = |name: &str| {
        let at = header.find(&format!("'{name}'"))? + name.len() + 2;
        Some(header[at..].trim_start_matches([':', ' ']))
    };
    let descr = field("descr").and_then(|v| v.split('\'').nth(1)).ok_or_else(|| invalid("no descr"))?;
    if field("fortran_order").is_some_and(|v| v.starts_with("True")) {
        return Err(invalid("Fortran order is not supported"));
    }
    let shape_text = field("shape").and_then(|v| v.strip_prefix('(')).and_then(|v| v.split(')').next());
    let shape: Vec<usize> = shape_text
        .ok_or_else(|| invalid("no shape"))?
        .split(',')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .map(|d| d.parse().map_err(|_| invalid("bad shape")))
        .collect::<Result<_, _>>()?;
    let count: usize = shape.iter().product();
    let body = &bytes[start + header_len..];
    let values: Vec<f32> = match descr {
        "<u2" | "|u2" if body.len() >= count * 2 => {
            body.chunks_exact(2).take(count).map(|c| u16::from_le_bytes([c[0], c[1]]) as f32).collect()
        }
        "<f4" if body.len() >= count * 4 => {
            body.chunks_exact(4).take(count).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
        }
        "<u2" | "|u2" | "<f4" => return Err(invalid("truncated data")),
        other => return Err(invalid(&format!("dtype {other} is not supported (use <u2 or <f4)"))),
    };
    Ok((shape, values))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_rejects_bad_files() {
        let dir = std::env::temp_dir().join(format!("gudsl-npy-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.npy");
        let data: Vec<f32> = (0..24).map(|i| i as f32 * 1.5).collect();
        save(&path, &[2, 3, 4], &data, Dtype::F32).unwrap();
        assert_eq!(load(&path).unwrap(), (vec![2, 3, 4], data.clone()));
        let bytes = fs::read(&path).unwrap();
        assert_eq!((u16::from_le_bytes([bytes[8], bytes[9]]) as usize + 10) % 64, 0, "header padded to 64");
        save(&path, &[24], &data, Dtype::U16).unwrap();
        let (shape, values) = load(&path).unwrap();
        assert_eq!(shape, vec![24]);
        assert_eq!(values, data.iter().map(|v| v.round()).collect::<Vec<_>>());
        fs::write(&path, b"not numpy").unwrap();
        assert!(load(&path).unwrap_err().to_string().contains("not a .npy file"));
        fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
        assert!(load(&path).unwrap_err().to_string().contains("truncated"));
        fs::remove_dir_all(&dir).unwrap();
    }
}
