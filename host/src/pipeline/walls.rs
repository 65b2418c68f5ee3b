//! Recorded calibration walls for phase normalization (`gudsl calibrate-phases --from DIR`):
//! static recordings of homogeneous walls, each a pair of channel files as a recording of raw
//! frames is (`files.rs`), its frames averaged and the black image subtracted — what
//! [`PhaseCalibration::fit`](gudsl_runtime::phase_normalization::PhaseCalibration::fit) takes.

use std::path::{Path, PathBuf};

use gudsl_runtime::{kernels::tof::subtract_black, Image};

use super::files::RawFiles;
use crate::access::ModelFiles;

/// The black image's channel files, subtracted from every wall when they are there.
const BLACK: &str = "black";

/// The walls in `dir` (the folder `files` reads beneath), in the order of their names:
/// `<wall>_a.npy` with `<wall>_b.npy` (raw frames of (4, H, W) or (N, 4, H, W), 16-bit values),
/// each the mean of its frames less the black image (`black_a.npy`/`black_b.npy`, one frame)
/// when there is one. Every problem is a message naming its file.
pub fn calibration_walls(files: &ModelFiles, dir: &Path) -> Result<Vec<(String, Image)>, String> {
    let present = files.folder(dir).map_err(|e| e.to_string())?.file_names().map_err(|e| e.to_string())?;
    let mut names: Vec<String> =
        present.iter().filter_map(|name| name.strip_suffix("_a.npy").map(str::to_string)).collect();
    let unpaired = names.iter().find(|name| !present.contains(&format!("{name}_b.npy")));
    if let Some(name) = unpaired {
        return Err(format!(
            "{} has no {}: a wall is two channel files",
            channel(dir, name, 'a').display(),
            channel(dir, name, 'b').display()
        ));
    }
    let black = match names.iter().position(|n| n == BLACK) {
        Some(at) => Some(mean_frame(files, dir, &names.remove(at))?),
        None => None,
    };
    if names.is_empty() {
        return Err(format!(
            "{} holds no wall: give each wall's channel files as <wall>_a.npy and <wall>_b.npy",
            dir.display()
        ));
    }
    names
        .into_iter()
        .map(|name| {
            let wall = mean_frame(files, dir, &name)?;
            let wall = match &black {
                Some(black) if (black.width, black.height) != (wall.width, wall.height) => {
                    return Err(format!(
                        "{}: the black image is {}×{}, this wall {}×{}",
                        channel(dir, &name, 'a').display(),
                        black.width,
                        black.height,
                        wall.width,
                        wall.height
                    ))
                }
                Some(black) => subtract_black(&wall, black),
                None => wall,
            };
            Ok((name, wall))
        })
        .collect()
}

fn channel(dir: &Path, name: &str, tap: char) -> PathBuf {
    dir.join(format!("{name}_{tap}.npy"))
}

/// The mean of the frames of `<name>_a.npy` and `<name>_b.npy` (8 planes).
fn mean_frame(files: &ModelFiles, dir: &Path, name: &str) -> Result<Image, String> {
    let (a, b) = (channel(dir, name, 'a'), channel(dir, name, 'b'));
    let recording = RawFiles::open(files, &a, &b)
        .map_err(|errors| errors.into_iter().map(|e| e.message).collect::<Vec<_>>().join("; "))?;
    let count = recording.extent.frames;
    let mut frames = recording.frames(count);
    let mut sum = frames.next_frame()?;
    for _ in 1..count {
        let frame = frames.next_frame()?;
        sum.data.iter_mut().zip(&frame.data).for_each(|(s, v)| *s += v);
    }
    sum.data.iter_mut().for_each(|s| *s /= count as f32);
    Ok(sum)
}
