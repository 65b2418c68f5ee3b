//! Pictures a model names (PNG, JPEG: a depth image, `QImage::load`), read one way: opened
//! through their folder (regular files beneath it, at most [`MAX_PICTURE_FILE_BYTES`]), their
//! size read from the header and refused above [`MAX_PICTURE_PIXELS`] before anything is
//! decoded, and decoded under the image crate's allocation limit — a 140 KB PNG that claims
//! 12 000 × 12 000 pixels is an error naming it, not gigabytes of memory.

use std::{
    io::{BufRead, BufReader, Cursor, Seek},
    path::Path,
};

use gudsl_files::Folder;
use image::{DynamicImage, ImageDecoder, ImageReader, Limits};

/// The most pixels a picture may have (8192 × 8192).
pub const MAX_PICTURE_PIXELS: u64 = 1 << 26;

/// The longest picture file read.
pub const MAX_PICTURE_FILE_BYTES: u64 = 1 << 30;

/// The most memory a decoder may allocate for one picture (RGBA of 16 bits at the pixel cap).
const MAX_DECODER_BYTES: u64 = MAX_PICTURE_PIXELS * 8;

/// Why a picture was not read: the file and what is wrong, said of it.
pub type PictureError = String;

/// A picture's width and height, from its header.
pub fn dimensions(folder: &Folder, path: &Path) -> Result<(u32, u32), PictureError> {
    let decoder = decoder(reader(opened(folder, path)?, path)?, path)?;
    Ok(decoder.dimensions())
}

/// The picture at `path` beneath `folder`, decoded.
pub fn decode(folder: &Folder, path: &Path) -> Result<DynamicImage, PictureError> {
    decoded(reader(opened(folder, path)?, path)?, path)
}

/// The picture in `bytes`, decoded as the file `path` would be: what the fuzz target feeds.
pub fn decode_bytes(bytes: &[u8], path: &Path) -> Result<DynamicImage, PictureError> {
    decoded(reader(Cursor::new(bytes), path)?, path)
}

fn opened(folder: &Folder, path: &Path) -> Result<BufReader<std::fs::File>, PictureError> {
    let opened = folder.open_file(path, MAX_PICTURE_FILE_BYTES).map_err(|e| e.to_string())?;
    Ok(BufReader::new(opened.file))
}

fn reader<R: BufRead + Seek>(source: R, path: &Path) -> Result<ImageReader<R>, PictureError> {
    let mut reader = ImageReader::new(source).with_guessed_format().map_err(|e| format!("{}: {e}", path.display()))?;
    reader.limits(limits());
    Ok(reader)
}

/// The decoder of what `reader` reads, its header read: refused above the pixel cap.
fn decoder<'a, R: BufRead + Seek + 'a>(
    reader: ImageReader<R>,
    path: &Path,
) -> Result<impl ImageDecoder + 'a, PictureError> {
    let decoder = reader.into_decoder().map_err(|e| format!("{}: {e}", path.display()))?;
    let (width, height) = decoder.dimensions();
    within_limit(path, width, height)?;
    Ok(decoder)
}

/// The picture `reader` reads, decoded once its header passed and within the memory cap (the
/// reservation `ImageReader::decode` makes).
fn decoded<R: BufRead + Seek>(reader: ImageReader<R>, path: &Path) -> Result<DynamicImage, PictureError> {
    let failed = |e: image::ImageError| format!("{}: {e}", path.display());
    let decoder = decoder(reader, path)?;
    limits().reserve(decoder.total_bytes()).map_err(failed)?;
    DynamicImage::from_decoder(decoder).map_err(failed)
}

fn limits() -> Limits {
    let mut limits = Limits::default();
    limits.max_alloc = Some(MAX_DECODER_BYTES);
    limits
}

fn within_limit(path: &Path, width: u32, height: u32) -> Result<(), PictureError> {
    match u64::from(width) * u64::from(height) {
        pixels if pixels > MAX_PICTURE_PIXELS => Err(format!(
            "{}: {width} × {height} pixels, more than the {MAX_PICTURE_PIXELS} a picture may have",
            path.display()
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PNG of `width` × `height` grey pixels of 16 bits whose rows the file does not hold (a
    /// header is all a check reads).
    fn png_header(width: u32, height: u32, rows: &[u8]) -> Vec<u8> {
        let mut ihdr = width.to_be_bytes().to_vec();
        ihdr.extend(height.to_be_bytes());
        ihdr.extend([16, 0, 0, 0, 0]);
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        for (kind, data) in [(&b"IHDR"[..], &ihdr[..]), (b"IDAT", rows), (b"IEND", &[])] {
            png.extend((data.len() as u32).to_be_bytes());
            let start = png.len();
            png.extend(kind);
            png.extend(data);
            png.extend(crc32(&png[start..]).to_be_bytes());
        }
        png
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &byte in bytes {
            crc ^= u32::from(byte);
            for _ in 0..8 {
                crc = if crc & 1 == 1 { 0xEDB8_8320 ^ (crc >> 1) } else { crc >> 1 };
            }
        }
        !crc
    }

    #[test]
    fn a_picture_larger_than_the_cap_is_refused_before_it_is_decoded() {
        // 12 000 × 12 000 claimed (it took 2.2 GB before): refused from the header alone.
        let claimed = png_header(12_000, 12_000, &[]);
        let error = decode_bytes(&claimed, Path::new("big.png")).unwrap_err();
        assert!(error.contains("12000 × 12000 pixels, more than the 67108864"), "{error}");
        // A picture within the cap whose rows are missing is an error, not a panic.
        let error = decode_bytes(&png_header(4, 4, &[]), Path::new("short.png")).unwrap_err();
        assert!(error.starts_with("short.png: "), "{error}");
    }
}
