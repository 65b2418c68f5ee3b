//! Files a pipeline reads. Raw frames: two arrays of 16-bit values, channel A and channel B,
//! shape (4, H, W) for one frame or (N, 4, H, W) for N (phase image, row, column), interleaved
//! into the runtime's 8-plane frames (`A0 B0 A1 B1 A2 B2 A3 B3`). Depth images: an array of
//! (H, W) or (N, H, W) values, or one 16-bit PNG. Arrays are `.npy` files or members of `.npz`
//! archives (`gudsl_formats::arrays`). Opening reads the headers only — what the editor checks
//! as the model is typed —; a run reads the values a frame at a time as it asks for them. Every problem is a
//! message naming the file and what was expected.

use std::{
    path::{Path, PathBuf},
    sync::Arc,
};

use gudsl_files::Folder;
use gudsl_formats::{
    arrays,
    frame_stream::{FrameStream, FramesWanted},
    picture,
};
use gudsl_runtime::Image;

use crate::access::ModelFiles;

/// What raw frames' channel files must hold.
const RAW: &str =
    "a .npy array of 16-bit values (uint16, or floating point from 0 to 65535) of shape (4, H, W) or (N, 4, H, W)";

/// What a depth file must hold.
const DEPTH: &str = "a .npy array of shape (H, W) or (N, H, W), or a 16-bit PNG";

/// Why a channel file cannot be read; `in_b` when channel B's file is the culprit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileError {
    pub message: String,
    pub in_b: bool,
}

/// Frames, rows and columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Extent {
    pub frames: usize,
    pub height: usize,
    pub width: usize,
}

/// A shape as NumPy writes it: `(4, 30, 40)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// The message of an array that cannot be read, with what was `expected`.
fn unreadable(error: arrays::ArrayError, expected: &str) -> String {
    format!("{error}; expected {expected}")
}

/// The channel files of a recording of raw frames.
#[derive(Debug, Clone)]
pub struct RawFiles {
    folder: Arc<Folder>,
    a: PathBuf,
    b: PathBuf,
    pub extent: Extent,
}

impl RawFiles {
    /// Checks both files' headers: every problem found, each naming its file.
    pub fn open(files: &ModelFiles, a: &Path, b: &Path) -> Result<RawFiles, Vec<FileError>> {
        let folder = files.folder(a).cloned().map_err(|e| vec![FileError { message: e.to_string(), in_b: false }])?;
        let (extent_a, extent_b) = (channel(&folder, a), channel(&folder, b));
        match (extent_a, extent_b) {
            (Ok(ea), Ok(eb)) if ea == eb => Ok(RawFiles { folder, a: a.to_path_buf(), b: b.to_path_buf(), extent: ea }),
            (Ok(ea), Ok(eb)) => Err(vec![FileError {
                message: format!(
                    "{} holds {} frame(s) of {}×{}, but {} holds {} of {}×{}: the channels of a recording have one shape",
                    a.display(),
                    ea.frames,
                    ea.width,
                    ea.height,
                    b.display(),
                    eb.frames,
                    eb.width,
                    eb.height
                ),
                in_b: true,
            }]),
            (a, b) => {
                let errors = [(a.err(), false), (b.err(), true)];
                Err(errors.into_iter().filter_map(|(e, in_b)| Some(FileError { message: e?, in_b })).collect())
            }
        }
    }

    /// The first `frames` frames (all of them when there are fewer), read one at a time as
    /// the run asks for them (`FrameStream`).
    pub fn frames(&self, frames: usize) -> RawFrames {
        let Extent { height, width, .. } = self.extent;
        let wanted = || FramesWanted {
            frame_values: 4 * width * height,
            frames: frames.min(self.extent.frames),
            expected: self.extent.frames * 4 * width * height,
        };
        RawFrames {
            a: FrameStream::open(self.folder.clone(), &self.a, wanted()),
            b: FrameStream::open(self.folder.clone(), &self.b, wanted()),
            paths: [self.a.clone(), self.b.clone()],
            extent: self.extent,
            next: 0,
        }
    }
}

/// A recording's frames as they are read.
pub struct RawFrames {
    a: FrameStream,
    b: FrameStream,
    paths: [PathBuf; 2],
    extent: Extent,
    /// The index of the next frame.
    next: usize,
}

impl RawFrames {
    /// The next frame: planes `A0 B0 A1 B1 A2 B2 A3 B3`.
    pub fn next_frame(&mut self) -> Result<Image, String> {
        let frame = self.next;
        self.next += 1;
        let [a, b] = [&self.a, &self.b].map(|stream| stream.next_frame());
        let a = sixteen_bits(a.map_err(|e| unreadable(e, RAW))?, &self.paths[0], frame)?;
        let b = sixteen_bits(b.map_err(|e| unreadable(e, RAW))?, &self.paths[1], frame)?;
        let Extent { height, width, .. } = self.extent;
        let n = width * height;
        let mut raw = Image::zeros(width, height, 8);
        for phase in 0..4 {
            raw.plane_mut(2 * phase).copy_from_slice(&a[phase * n..(phase + 1) * n]);
            raw.plane_mut(2 * phase + 1).copy_from_slice(&b[phase * n..(phase + 1) * n]);
        }
        Ok(raw)
    }
}

/// A channel file's extent, from its header.
fn channel(folder: &Folder, path: &Path) -> Result<Extent, String> {
    let (shape, dtype) = arrays::header(folder, path).map_err(|e| unreadable(e, RAW))?;
    // Raw values are the camera's 16-bit units whatever the dtype: integers as recorded, or
    // floating point (frames averaged or calibrated), each checked as it is read.
    if dtype.kind == arrays::Kind::Bool {
        return Err(format!("{} has dtype {dtype}; expected {RAW}", path.display()));
    }
    match shape[..] {
        [4, height, width] if height > 0 && width > 0 => Ok(Extent { frames: 1, height, width }),
        [frames, 4, height, width] if frames > 0 && height > 0 && width > 0 => Ok(Extent { frames, height, width }),
        _ => Err(format!("{} has shape {}; expected {RAW}", path.display(), shape_text(&shape))),
    }
}

/// A frame of a channel file whose values are 16-bit values (a NaN is none).
fn sixteen_bits(values: Vec<f32>, path: &Path, frame: usize) -> Result<Vec<f32>, String> {
    match values.iter().position(|v| !(0.0..=65535.0).contains(v)) {
        Some(at) => Err(format!(
            "{} holds {} at index {at} of frame {frame}, outside 0..=65535; expected {RAW}",
            path.display(),
            values[at]
        )),
        None => Ok(values),
    }
}

/// A file of depth images: an array or a 16-bit PNG.
#[derive(Debug, Clone)]
pub struct DepthFile {
    folder: Arc<Folder>,
    path: PathBuf,
    png: bool,
    pub extent: Extent,
}

impl DepthFile {
    /// Checks the file's header.
    pub fn open(files: &ModelFiles, path: &Path) -> Result<DepthFile, String> {
        let folder = files.folder(path).cloned().map_err(|e| e.to_string())?;
        let png = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let extent = if png {
            let (width, height) = picture::dimensions(&folder, path).map_err(|e| format!("{e}; expected {DEPTH}"))?;
            Extent { frames: 1, height: height as usize, width: width as usize }
        } else {
            let (shape, _) = arrays::header(&folder, path).map_err(|e| unreadable(e, DEPTH))?;
            match shape[..] {
                [height, width] if height > 0 && width > 0 => Extent { frames: 1, height, width },
                [frames, height, width] if frames > 0 && height > 0 && width > 0 => Extent { frames, height, width },
                _ => return Err(format!("{} has shape {}; expected {DEPTH}", path.display(), shape_text(&shape))),
            }
        };
        Ok(DepthFile { folder, path: path.to_path_buf(), png, extent })
    }

    /// The file, as the model names it.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The first `frames` images (all when there are fewer) in metres, read one at a time:
    /// an array's values as they are, a PNG's times `scale`.
    pub fn frames(&self, frames: usize, scale: f32) -> DepthFrames {
        let Extent { height, width, .. } = self.extent;
        let source = match self.png {
            true => Depths::Picture(Some(self.folder.clone())),
            false => Depths::Array(FrameStream::open(
                self.folder.clone(),
                &self.path,
                FramesWanted {
                    frame_values: width * height,
                    frames: frames.min(self.extent.frames),
                    expected: self.extent.frames * width * height,
                },
            )),
        };
        DepthFrames { source, path: self.path.clone(), extent: self.extent, scale }
    }
}

/// A file's depth images as they are read.
pub struct DepthFrames {
    source: Depths,
    path: PathBuf,
    extent: Extent,
    scale: f32,
}

enum Depths {
    /// A PNG's one image, decoded when it is asked for (`None` once it was).
    Picture(Option<Arc<Folder>>),
    Array(FrameStream),
}

impl DepthFrames {
    /// The next depth image, in metres.
    pub fn next_frame(&mut self) -> Result<Image, String> {
        let Extent { height, width, .. } = self.extent;
        let values = match &mut self.source {
            // The stream refuses an array whose shape changed since it was opened.
            Depths::Array(stream) => stream.next_frame().map_err(|e| unreadable(e, DEPTH))?,
            Depths::Picture(folder) => {
                let folder = folder.take().ok_or_else(|| format!("{} holds one image", self.path.display()))?;
                let values = picture_values(&folder, &self.path)?;
                changed_since_opened(&self.path, values.len(), width * height)?;
                values.into_iter().map(|v| v * self.scale).collect()
            }
        };
        Ok(Image { width, height, planes: 1, data: values })
    }
}

/// A greyscale PNG's values (16 or 8 bits).
fn picture_values(folder: &Folder, path: &Path) -> Result<Vec<f32>, String> {
    match picture::decode(folder, path).map_err(|e| format!("{e}; expected {DEPTH}"))? {
        image::DynamicImage::ImageLuma16(grey) => Ok(grey.into_raw().into_iter().map(f32::from).collect()),
        image::DynamicImage::ImageLuma8(grey) => Ok(grey.into_raw().into_iter().map(f32::from).collect()),
        other => {
            Err(format!("{} is a {:?} PNG; expected a greyscale PNG of 16 (or 8) bits", path.display(), other.color()))
        }
    }
}

/// An error unless a file still holds the `expected` values its header promised when it was
/// opened (it may have been written again since).
fn changed_since_opened(path: &Path, values: usize, expected: usize) -> Result<(), String> {
    match values == expected {
        true => Ok(()),
        false => Err(format!(
            "{} holds {values} values, not the {expected} it held when the run was prepared: it changed meanwhile",
            path.display()
        )),
    }
}
