//! Files a pipeline reads. Raw frames: two arrays of 16-bit values, channel A and channel B,
//! shape (4, H, W) for one frame or (N, 4, H, W) for N (phase image, row, column), interleaved
//! into the runtime's 8-plane frames (`A0 B0 A1 B1 A2 B2 A3 B3`); or two topics of a ROS 2 bag
//! (`rec.mcap:/tof/raw_a`), a message a frame holding its four phase images one below the
//! other (4·H rows). Depth images: an array of (H, W) or (N, H, W) values, a topic of a bag,
//! one picture (a 16-bit PNG, an OpenEXR image) or a sequence of them (`depth/*.png`, in name
//! order). Arrays are `.npy` files or members of `.npz` archives (`gudsl_formats::arrays`).
//! Opening reads the headers only — what the editor checks as the model is typed —; a run
//! reads the values a frame at a time as it asks for them. Every problem is a message naming
//! the file and what was expected. [`stamped_path`] says which file (or folder) a path's
//! contents depend on.

use std::{
    path::{Path, PathBuf},
    sync::Arc,
};

use gudsl_files::Folder;
use gudsl_formats::{
    arrays,
    bag::{self, Place},
    frame_stream::{FrameStream, FramesWanted},
    openexr, picture,
};
use gudsl_runtime::Image;

use crate::access::ModelFiles;

/// What raw frames' channel files must hold.
const RAW: &str = "a .npy array of 16-bit values (uint16, or floating point from 0 to 65535) of shape (4, H, W) or \
     (N, 4, H, W), or a bag's topic of images of 4·H rows (`rec.mcap:/topic`)";

/// What a depth file must hold.
const DEPTH: &str = "a .npy array of shape (H, W) or (N, H, W), a bag's topic of images (`rec.mcap:/topic`), or \
     pictures: a 16-bit PNG or an OpenEXR image, or a sequence of them (`depth/*.png`)";

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
        let stream = |path: &Path| match Place::parse(path) {
            Some(place) => bag::images(self.folder.clone(), &place, frames, (width, 4 * height)),
            None => FrameStream::open(self.folder.clone(), path, wanted()),
        };
        RawFrames {
            a: stream(&self.a),
            b: stream(&self.b),
            paths: [self.a.clone(), self.b.clone()],
            extent: self.extent,
            next: 0,
            stamp: None,
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
    /// When the last frame read was recorded (a bag's), ns.
    pub stamp: Option<u64>,
}

impl RawFrames {
    /// The next frame: planes `A0 B0 A1 B1 A2 B2 A3 B3`.
    pub fn next_frame(&mut self) -> Result<Image, String> {
        let frame = self.next;
        self.next += 1;
        let [a, b] = [&self.a, &self.b].map(|stream| stream.next_stamped());
        let (a, stamp) = a.map_err(|e| unreadable(e, RAW))?;
        self.stamp = stamp;
        let b = b.map(|(values, _)| values);
        let a = sixteen_bits(a, &self.paths[0], frame)?;
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
    if let Some(place) = Place::parse(path) {
        let topic = bag::image_topic(folder, &place)?;
        return match topic.height % 4 {
            0 => Ok(Extent { frames: topic.messages, height: topic.height / 4, width: topic.width }),
            _ => Err(format!(
                "{} holds images of {} rows, not four phase images one below the other; expected {RAW}",
                path.display(),
                topic.height
            )),
        };
    }
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

/// A file of depth images: an array, a bag's topic, or pictures.
#[derive(Debug, Clone)]
pub struct DepthFile {
    folder: Arc<Folder>,
    path: PathBuf,
    stored: Stored,
    pub extent: Extent,
}

/// How a file source's depth images are stored.
#[derive(Debug, Clone)]
enum Stored {
    /// A `.npy` array or `.npz` member of shape (H, W) or (N, H, W): metres.
    Array,
    /// A topic of images in a bag: metres when floats, units of `scale` when integers.
    Bag { place: Place, integer: bool },
    /// Pictures, one a frame, in name order: a PNG's values are units of `scale`, an EXR's metres.
    Pictures(Vec<PathBuf>),
}

impl DepthFile {
    /// Checks the file's header (a sequence's first picture's, and that every name is a picture's).
    pub fn open(files: &ModelFiles, path: &Path) -> Result<DepthFile, String> {
        let folder = files.folder(path).cloned().map_err(|e| e.to_string())?;
        let (stored, extent) = if let Some(place) = Place::parse(path) {
            let topic = bag::image_topic(&folder, &place)?;
            let extent = Extent { frames: topic.messages, height: topic.height, width: topic.width };
            (Stored::Bag { place, integer: topic.integer }, extent)
        } else if is_picture(path) || is_pattern(path) {
            let pictures = pictures_named(&folder, path)?;
            let (width, height) = picture_size(&folder, &pictures[0])?;
            (Stored::Pictures(pictures.clone()), Extent { frames: pictures.len(), height, width })
        } else {
            let (shape, _) = arrays::header(&folder, path).map_err(|e| unreadable(e, DEPTH))?;
            let extent = match shape[..] {
                [height, width] if height > 0 && width > 0 => Extent { frames: 1, height, width },
                [frames, height, width] if frames > 0 && height > 0 && width > 0 => Extent { frames, height, width },
                _ => return Err(format!("{} has shape {}; expected {DEPTH}", path.display(), shape_text(&shape))),
            };
            (Stored::Array, extent)
        };
        Ok(DepthFile { folder, path: path.to_path_buf(), stored, extent })
    }

    /// The file, as the model names it.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The first `frames` images (all when there are fewer) in metres, read one at a time:
    /// an array's values and floating-point images as they are, integer ones times `scale`.
    pub fn frames(&self, frames: usize, scale: f32) -> DepthFrames {
        let Extent { height, width, .. } = self.extent;
        let frames = frames.min(self.extent.frames);
        let (source, scale) = match &self.stored {
            Stored::Array => {
                let wanted = FramesWanted {
                    frame_values: width * height,
                    frames,
                    expected: self.extent.frames * width * height,
                };
                (Depths::Stream(FrameStream::open(self.folder.clone(), &self.path, wanted)), 1.0)
            }
            Stored::Bag { place, integer } => {
                let stream = bag::images(self.folder.clone(), place, frames, (width, height));
                (Depths::Stream(stream), if *integer { scale } else { 1.0 })
            }
            Stored::Pictures(paths) => (Depths::Pictures(self.folder.clone(), paths[..frames].to_vec().into()), scale),
        };
        DepthFrames { source, extent: self.extent, scale, stamp: None }
    }
}

/// Whether `path` names one picture (PNG, EXR).
fn is_picture(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png") || e.eq_ignore_ascii_case("exr"))
}

/// Whether `path`'s file name is a pattern (`*`, `?`, `[…]`) naming a sequence of pictures.
fn is_pattern(path: &Path) -> bool {
    path.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.contains(['*', '?', '[']))
}

/// The pictures `path` names: itself, or the files of its folder its file name's pattern
/// matches, in name order; an error when none does or one is no picture.
fn pictures_named(folder: &Folder, path: &Path) -> Result<Vec<PathBuf>, String> {
    files_named(folder, path, (is_picture, "PNG or EXR picture"), DEPTH)
}

/// The files `path` names — itself, or the files of its folder its file name's pattern
/// matches, in name order — each of a `kind` (a test, and what it is called); an error saying
/// what was `expected` when none does or one is of another kind.
fn files_named(
    folder: &Folder,
    path: &Path,
    kind: (fn(&Path) -> bool, &str),
    expected: &str,
) -> Result<Vec<PathBuf>, String> {
    if !is_pattern(path) {
        return Ok(vec![path.to_path_buf()]);
    }
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    let pattern = glob::Pattern::new(name).map_err(|e| format!("{}: `{name}` is no pattern ({e})", path.display()))?;
    let parent = path.parent().unwrap_or(Path::new(""));
    let names = folder.file_names_in(parent).map_err(|e| e.to_string())?;
    let matched: Vec<PathBuf> = names.iter().filter(|n| pattern.matches(n)).map(|n| parent.join(n)).collect();
    if let Some(other) = matched.iter().find(|p| !kind.0(p)) {
        return Err(format!(
            "{} matches {}, which is no {}; expected {expected}",
            path.display(),
            other.display(),
            kind.1
        ));
    }
    match matched.is_empty() {
        true => Err(format!("no file matches {}; expected {expected}", path.display())),
        false => Ok(matched),
    }
}

/// What a cloud file must be.
const CLOUD: &str =
    "a PLY or PCD point cloud, a sequence of them (`clouds/*.ply`), or a bag's topic of PointCloud2 (`rec.mcap:/topic`)";

fn is_cloud(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("ply") || e.eq_ignore_ascii_case("pcd"))
}

/// Point clouds, one a frame: a PLY or PCD file, a sequence of them, or a bag's topic.
#[derive(Debug, Clone)]
pub struct CloudFiles {
    folder: Arc<Folder>,
    stored: StoredClouds,
    /// How many clouds there are.
    pub count: usize,
}

#[derive(Debug, Clone)]
enum StoredClouds {
    Files(Vec<PathBuf>),
    Bag(Place),
}

impl CloudFiles {
    /// The clouds `path` names, checked: a file's (or a sequence's first) read through, a
    /// topic's summary and first message.
    pub fn open(files: &ModelFiles, path: &Path) -> Result<CloudFiles, String> {
        let folder = files.folder(path).cloned().map_err(|e| e.to_string())?;
        if let Some(place) = Place::parse(path) {
            let count = bag::cloud_topic(&folder, &place)?;
            return Ok(CloudFiles { folder, stored: StoredClouds::Bag(place), count });
        }
        let paths = match is_cloud(path) || is_pattern(path) {
            true => files_named(&folder, path, (is_cloud, "PLY or PCD point cloud"), CLOUD)?,
            false => return Err(format!("{} is no PLY or PCD file; expected {CLOUD}", path.display())),
        };
        read_cloud(&folder, &paths[0])?;
        Ok(CloudFiles { folder, count: paths.len(), stored: StoredClouds::Files(paths) })
    }

    /// The first `frames` clouds, read one at a time as the run asks for them.
    pub fn clouds(&self, frames: usize) -> Clouds {
        let frames = frames.min(self.count);
        match &self.stored {
            StoredClouds::Files(paths) => Clouds::Files(self.folder.clone(), paths[..frames].to_vec().into()),
            StoredClouds::Bag(place) => Clouds::Stream(bag::clouds(self.folder.clone(), place, frames)),
        }
    }
}

/// A source's clouds as they are read.
pub enum Clouds {
    Files(Arc<Folder>, std::collections::VecDeque<PathBuf>),
    /// A topic's, each as its points' `x y z nx ny nz` one after the other.
    Stream(FrameStream),
}

impl Clouds {
    /// The next cloud's points and normals (zero where it has none).
    pub fn next_cloud(&mut self) -> Result<gudsl_formats::ply::Points, String> {
        match self {
            Clouds::Files(folder, paths) => read_cloud(folder, &paths.pop_front().ok_or("the clouds are all read")?),
            Clouds::Stream(stream) => {
                let values = stream.next_frame().map_err(|e| format!("{e}; expected {CLOUD}"))?;
                let point = |v: &[f32]| [v[0], v[1], v[2]];
                Ok(values.chunks_exact(6).map(|v| (point(v), point(&v[3..]))).unzip())
            }
        }
    }
}

/// The points and normals of a PLY or PCD file.
fn read_cloud(folder: &Folder, path: &Path) -> Result<gudsl_formats::ply::Points, String> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("pcd")) {
        return gudsl_formats::pcd::read(folder, path);
    }
    let bytes = folder.read(path, gudsl_formats::pcd::MAX_PCD_BYTES).map_err(|e| e.to_string())?;
    gudsl_formats::ply::read(&bytes)
        .map_err(|e| format!("{}: is not a readable PLY file ({e}); expected {CLOUD}", path.display()))
}

/// A picture's width and height, from its header.
fn picture_size(folder: &Folder, path: &Path) -> Result<(usize, usize), String> {
    if is_exr(path) {
        return openexr::dimensions(folder, path);
    }
    let (width, height) = picture::dimensions(folder, path).map_err(|e| format!("{e}; expected {DEPTH}"))?;
    Ok((width as usize, height as usize))
}

fn is_exr(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// The file (or, for a sequence, the folder) a file parameter's contents depend on: what a
/// prepared pipeline's stamp is taken of.
pub fn stamped_path(path: &Path) -> PathBuf {
    if let Some(place) = Place::parse(path) {
        return place.file;
    }
    if is_pattern(path) {
        return path.parent().map(Path::to_path_buf).unwrap_or_default();
    }
    arrays::Source::parse(path).file
}

/// A file's depth images as they are read.
pub struct DepthFrames {
    source: Depths,
    extent: Extent,
    /// Metres per unit of an integer image.
    scale: f32,
    /// When the last image read was recorded (a bag's), ns.
    pub stamp: Option<u64>,
}

enum Depths {
    /// An array's or a topic's images, read ahead on their thread.
    Stream(FrameStream),
    /// Pictures, each decoded when its frame is asked for.
    Pictures(Arc<Folder>, std::collections::VecDeque<PathBuf>),
}

impl DepthFrames {
    /// The next depth image, in metres.
    pub fn next_frame(&mut self) -> Result<Image, String> {
        let Extent { height, width, .. } = self.extent;
        let values = match &mut self.source {
            // The stream refuses an array whose shape changed since it was opened.
            Depths::Stream(stream) => {
                let (values, stamp) = stream.next_stamped().map_err(|e| unreadable(e, DEPTH))?;
                self.stamp = stamp;
                values.into_iter().map(|v| v * self.scale).collect()
            }
            Depths::Pictures(folder, paths) => {
                let path = paths.pop_front().ok_or("the pictures are all read")?;
                let (values, integer) = picture_values(folder, &path)?;
                changed_since_opened(&path, values.len(), width * height)?;
                let scale = if integer { self.scale } else { 1.0 };
                values.into_iter().map(|v| v * scale).collect()
            }
        };
        Ok(Image { width, height, planes: 1, data: values })
    }
}

/// A picture's values, and whether they are integers: a greyscale PNG's (16 or 8 bits), an
/// EXR's depth channel.
fn picture_values(folder: &Folder, path: &Path) -> Result<(Vec<f32>, bool), String> {
    if is_exr(path) {
        return openexr::read_depth(folder, path).map(|(_, _, values)| (values, false));
    }
    match picture::decode(folder, path).map_err(|e| format!("{e}; expected {DEPTH}"))? {
        image::DynamicImage::ImageLuma16(grey) => Ok((grey.into_raw().into_iter().map(f32::from).collect(), true)),
        image::DynamicImage::ImageLuma8(grey) => Ok((grey.into_raw().into_iter().map(f32::from).collect(), true)),
        other => {
            Err(format!("{} is a {:?} PNG; expected a greyscale PNG of 16 (or 8) bits", path.display(), other.color()))
        }
    }
}

/// An error unless a picture holds the `expected` values (`width`×`height`) its sequence's
/// first had when the run was prepared (it may have been written again since).
fn changed_since_opened(path: &Path, values: usize, expected: usize) -> Result<(), String> {
    match values == expected {
        true => Ok(()),
        false => Err(format!(
            "{} holds {values} values, not the {expected} of the sequence's first picture when the run was \
             prepared: the pictures of a sequence have one size, and a file must not change while it is read",
            path.display()
        )),
    }
}
