//! Pictures a model names (PNG, JPEG: a depth image, `QImage::load`), read one way: opened
//! through their folder (regular files beneath it, at most [`MAX_PICTURE_FILE_BYTES`]), their
//! size read from the header and refused above [`MAX_PICTURE_PIXELS`] before anything is
//! decoded, and decoded under the image crate's allocation limit — a 140 KB PNG that claims
//! 12 000 × 12 000 pixels is an error naming it, not gigabytes of memory.

use std::{io::BufReader, path::Path};

use gudsl_files::Folder;
use image::{DynamicImage, ImageReader, Limits};

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
    let reader = reader(folder, path)?;
    let (width, height) = reader.into_dimensions().map_err(|e| format!("{}: {e}", path.display()))?;
    within_limit(path, width, height)?;
    Ok((width, height))
}

/// The picture at `path` beneath `folder`, decoded.
pub fn decode(folder: &Folder, path: &Path) -> Result<DynamicImage, PictureError> {
    let (width, height) = dimensions(folder, path)?;
    let mut reader = reader(folder, path)?;
    reader.limits(limits());
    let decoded = reader.decode().map_err(|e| format!("{}: {e}", path.display()))?;
    if (decoded.width(), decoded.height()) != (width, height) {
        return Err(format!("{}: changed while it was read", path.display()));
    }
    Ok(decoded)
}

fn reader(folder: &Folder, path: &Path) -> Result<ImageReader<BufReader<std::fs::File>>, PictureError> {
    let opened = folder.open_file(path, MAX_PICTURE_FILE_BYTES).map_err(|e| e.to_string())?;
    let mut reader = ImageReader::new(BufReader::new(opened.file))
        .with_guessed_format()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    reader.limits(limits());
    Ok(reader)
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
