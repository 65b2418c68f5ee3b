//! Recorded arrays read a frame at a time: a `.npy` file or `.npz` member of shape (N, …) is
//! read on a thread of its own, one frame ahead of the run, so a run holds two frames of a
//! recording in memory however long it is, and a run of one frame reads one (or two) — not the
//! whole file. Dropping the stream stops the reading. (Fortran-order arrays are read whole
//! first: their frames are not contiguous.)

use std::{
    path::{Path, PathBuf},
    sync::{mpsc, Arc},
};

use gudsl_files::Folder;
use npyz::Order;

use crate::arrays::{self, ArrayError};

/// A frame's values and, when the file records it, its time (ns since the epoch).
pub type Stamped = (Vec<f32>, Option<u64>);

/// The frames of one array, in order.
pub struct FrameStream {
    frames: mpsc::Receiver<Result<Stamped, ArrayError>>,
    path: PathBuf,
}

/// Which frames to read of which array.
pub struct FramesWanted {
    /// Values in one frame (C order).
    pub frame_values: usize,
    /// How many frames to read, from the first.
    pub frames: usize,
    /// How many values the array held when its header was checked (a file written again
    /// since is refused, not misread).
    pub expected: usize,
}

impl FrameStream {
    /// Starts reading `wanted` of the array at `path` (beneath `folder`).
    pub fn open(folder: Arc<Folder>, path: &Path, wanted: FramesWanted) -> FrameStream {
        let reading = path.to_path_buf();
        FrameStream::spawn(path, move |send| send_frames(&folder, &reading, &wanted, &mut |frame| send(frame, None)))
    }

    /// Frames of the file `path` that `read` gives, on a thread of its own: it hands each frame
    /// and its time to the function it is given, which says whether to go on (`false`: the
    /// stream was dropped or every frame wanted was read).
    pub fn spawn<R>(path: &Path, read: R) -> FrameStream
    where
        R: FnOnce(&mut dyn FnMut(Vec<f32>, Option<u64>) -> bool) -> Result<(), ArrayError> + Send + 'static,
    {
        let (sender, frames) = mpsc::sync_channel(0);
        std::thread::spawn(move || {
            let mut send = |frame: Vec<f32>, stamp: Option<u64>| sender.send(Ok((frame, stamp))).is_ok();
            if let Err(error) = read(&mut send) {
                let _ = sender.send(Err(error));
            }
        });
        FrameStream { frames, path: path.to_path_buf() }
    }

    /// The next frame's values.
    pub fn next_frame(&self) -> Result<Vec<f32>, ArrayError> {
        self.next_stamped().map(|(values, _)| values)
    }

    /// The next frame's values and its time, when the file records it.
    pub fn next_stamped(&self) -> Result<Stamped, ArrayError> {
        self.frames.recv().unwrap_or_else(|_| {
            Err(ArrayError::new(&self.path, std::io::ErrorKind::UnexpectedEof, "holds no more frames"))
        })
    }
}

/// Reads the frames and sends each; stops early when the stream was dropped.
fn send_frames(
    folder: &Folder,
    path: &Path,
    wanted: &FramesWanted,
    sender: &mut dyn FnMut(Vec<f32>) -> bool,
) -> Result<(), ArrayError> {
    arrays::with_array(folder, path, |file, shown| {
        let shape = arrays::shape_of(&file);
        let held: usize = shape.iter().product();
        if held != wanted.expected {
            let message = format!(
                "holds {held} values, not the {} it held when the run was prepared: it changed meanwhile",
                wanted.expected
            );
            return Err(ArrayError::invalid(shown, message));
        }
        let dtype = arrays::dtype_of(&file, shown)?;
        let chunk = wanted.frame_values.max(1);
        let mut left = wanted.frames;
        let mut send = |frame: Vec<f32>| {
            left = left.saturating_sub(1);
            sender(frame) && left > 0
        };
        if wanted.frames == 0 {
            return Ok(());
        }
        if file.order() == Order::Fortran {
            let values = arrays::values(file, dtype).map_err(|e| ArrayError::io(shown, e))?;
            for frame in arrays::to_c_order(&values, &shape).chunks(chunk) {
                if !send(frame.to_vec()) {
                    break;
                }
            }
            return Ok(());
        }
        arrays::chunks_of(file, dtype, chunk, &mut send).map_err(|e| ArrayError::io(shown, e))
    })
}
