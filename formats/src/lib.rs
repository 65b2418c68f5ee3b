//! The file formats a model names, read without trusting a header: NumPy arrays (`.npy`,
//! `.npz` members; whole, or a frame at a time for recordings), pictures (PNG, JPEG) and PLY
//! point clouds. A reader
//! checks every size a file claims against what the file holds before it allocates, and each
//! has a fuzz target (`fuzz/`). No GPU here: the runtime, the host and the tools share it.

pub mod arrays;
pub mod bag;
pub mod frame_stream;
pub mod openexr;
pub mod pcd;
pub mod picture;
pub mod ply;
pub mod ros2;
