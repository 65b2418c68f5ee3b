//! The car-reconstruction chain of chapter 6 before registration, one kernel a module with its
//! CPU reference: amplitude masking (eq. 6.1), 3×3 outlier removal, background segmentation on
//! intensity AND distance with morphology, and the point cloud with its normals. A distance of 0
//! marks an invalid pixel. The median background model is host code.

use crate::Image;

pub mod apply_mask;
pub mod mask_amplitude;
pub mod morphology;
pub mod normals;
pub mod point_cloud;
pub mod remove_outliers;
pub mod segment;

pub use apply_mask::apply_mask;
pub(crate) use apply_mask::ApplyMask;
pub use mask_amplitude::mask_amplitude;
pub(crate) use mask_amplitude::MaskAmplitude;
pub use morphology::morphology;
pub(crate) use morphology::Morphology;
pub use normals::normals;
pub(crate) use normals::Normals;
pub use point_cloud::point_cloud;
pub(crate) use point_cloud::PointCloud;
pub use remove_outliers::remove_outliers;
pub(crate) use remove_outliers::RemoveOutliers;
pub use segment::segment;
pub(crate) use segment::Segment;

/// The median background model (sec. 6.5.2): per pixel, the median over frames of the empty scene.
pub fn background(frames: &[Image]) -> Image {
    let first = &frames[0];
    let mut out = Image::zeros(first.width, first.height, first.planes);
    let mut values = Vec::with_capacity(frames.len());
    for i in 0..first.data.len() {
        values.clear();
        values.extend(frames.iter().map(|f| f.data[i]));
        values.sort_by(f32::total_cmp);
        out.data[i] = values[values.len() / 2];
    }
    out
}
