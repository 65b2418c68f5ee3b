//! Files a pipeline reads: raw frames as two `.npy` arrays of 16-bit values, channel A and
//! channel B, shape (4, H, W) for one frame or (N, 4, H, W) for N (phase image, row, column),
//! interleaved into the runtime's 8-plane frames (`A0 B0 A1 B1 A2 B2 A3 B3`). Every problem is
//! a message naming the file and what was expected.

use std::path::Path;

use gudsl_runtime::{npy, Image};

/// Why a pair of channel files cannot be read; `in_b` when channel B's file is the culprit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileError {
    pub message: String,
    pub in_b: bool,
}

/// The frames of channel files `a` and `b`.
pub fn raw_frames(a: &Path, b: &Path) -> Result<Vec<Image>, FileError> {
    let (shape_a, data_a) = channel(a).map_err(|message| FileError { message, in_b: false })?;
    let (shape_b, data_b) = channel(b).map_err(|message| FileError { message, in_b: true })?;
    if shape_a != shape_b {
        return Err(FileError {
            message: format!(
                "{} has shape {:?}, but {} has {:?}: the channels of a recording have one shape",
                a.display(),
                shape_a,
                b.display(),
                shape_b
            ),
            in_b: true,
        });
    }
    let (frames, height, width) = shape_a;
    let n = width * height;
    Ok((0..frames)
        .map(|f| {
            let mut raw = Image::zeros(width, height, 8);
            for phase in 0..4 {
                let from = (f * 4 + phase) * n;
                raw.plane_mut(2 * phase).copy_from_slice(&data_a[from..from + n]);
                raw.plane_mut(2 * phase + 1).copy_from_slice(&data_b[from..from + n]);
            }
            raw
        })
        .collect())
}

/// Frames, rows and columns of a channel file.
type Extent = (usize, usize, usize);

/// One channel file: its extent and its values.
fn channel(path: &Path) -> Result<(Extent, Vec<f32>), String> {
    let expected = "a .npy array of 16-bit values of shape (4, H, W) or (N, 4, H, W)";
    let (shape, values) = npy::load(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => format!("{} does not exist; expected {expected}", path.display()),
        _ => format!("{e}; expected {expected}"),
    })?;
    match shape[..] {
        [4, h, w] if h > 0 && w > 0 => Ok(((1, h, w), values)),
        [n, 4, h, w] if n > 0 && h > 0 && w > 0 => Ok(((n, h, w), values)),
        _ => Err(format!("{} has shape {shape:?}; expected {expected}", path.display())),
    }
}
