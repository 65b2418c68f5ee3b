//! Registration of ToF point clouds (sec. 6.5.3): projective point-to-plane ICP iterated with
//! the reduction on the CPU reference or on the GPU (one 29-value readback per iteration), the
//! accumulation of registered clouds into one model, and its export as PLY.

use std::fmt;
use std::io::{self, Write};

use crate::camera::{apply, compose, Intrinsics, Pose};
use crate::kernels::car::{normals, point_cloud};
use crate::kernels::icp::{self, SUMS};
use crate::{ChainError, ChainRun, Gpu, Image, Kernel, Pipeline, Shape};

/// A point cloud with its normals, both 3-plane images (x, y, z); a point with z = 0 is invalid.
#[derive(Debug, Clone, PartialEq)]
pub struct Cloud {
    pub points: Image,
    pub normals: Image,
}

impl Cloud {
    /// The cloud of a distance image (polar → Cartesian with the camera's rays, normals by
    /// central differences).
    pub fn from_distance(distance: &Image, intrinsics: &Intrinsics) -> Cloud {
        let points = point_cloud(distance, &intrinsics.rays());
        let normals = normals(&points);
        Cloud { points, normals }
    }
}

/// The rejection thresholds and the iteration budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IcpSettings {
    /// Pairs farther apart are rejected (sec. 6.5.3: 0.2 m).
    pub max_distance: f32,
    /// Pairs whose normals differ more are rejected (sec. 6.5.3: 20°).
    pub max_angle_degrees: f32,
    pub max_iterations: usize,
    /// Fewer pairs than this is no registration.
    pub min_pairs: usize,
}

impl Default for IcpSettings {
    fn default() -> IcpSettings {
        IcpSettings { max_distance: 0.2, max_angle_degrees: 20.0, max_iterations: 20, min_pairs: 500 }
    }
}

/// A registration: the pose taking the source cloud into the model's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Registration {
    pub pose: Pose,
    pub iterations: usize,
    /// Pairs and root-mean-square point-to-plane distance (metres) at the last iteration.
    pub pairs: usize,
    pub rms: f32,
    /// Whether the last increment was below 0.01 mm and 0.001°.
    pub converged: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub enum RegistrationError {
    /// The clouds overlap in too few pixels at this pose.
    TooFewPairs { pairs: usize, needed: usize },
    /// The pairs do not fix all six degrees of freedom (e.g. one plane).
    Degenerate,
    /// The GPU reduction could not run (clouds of another size than the camera's, a lost device).
    Pipeline(ChainError),
}

impl fmt::Display for RegistrationError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            RegistrationError::TooFewPairs { pairs, needed } => write!(
                f,
                "ICP found {pairs} point pairs, needs {needed}: the clouds barely overlap at the initial pose"
            ),
            RegistrationError::Degenerate => {
                write!(f, "ICP pairs do not fix the pose (a single plane?): the 6×6 system is singular")
            }
            RegistrationError::Pipeline(error) => write!(f, "ICP on the GPU: {error}"),
        }
    }
}

impl std::error::Error for RegistrationError {}

/// Iterates ICP from `initial`, `sums_at(pose)` reducing the pairs at a pose.
pub fn iterate(
    settings: &IcpSettings,
    initial: Pose,
    mut sums_at: impl FnMut(&Pose) -> Result<[f64; SUMS], RegistrationError>,
) -> Result<Registration, RegistrationError> {
    let mut pose = initial;
    for iteration in 1..=settings.max_iterations {
        let sums = sums_at(&pose)?;
        let pairs = sums[27] as usize;
        if pairs < settings.min_pairs {
            return Err(RegistrationError::TooFewPairs { pairs, needed: settings.min_pairs });
        }
        let x = icp::solve(&sums).ok_or(RegistrationError::Degenerate)?;
        pose = icp::compose(&x, &pose);
        let rotation = x[..3].iter().map(|v| v * v).sum::<f64>().sqrt();
        let translation = x[3..].iter().map(|v| v * v).sum::<f64>().sqrt();
        let converged = rotation < 1e-3f64.to_radians() && translation < 1e-5;
        if converged || iteration == settings.max_iterations {
            let rms = (sums[28] / sums[27]).sqrt() as f32;
            return Ok(Registration { pose, iterations: iteration, pairs, rms, converged });
        }
    }
    unreachable!("max_iterations is at least one: {settings:?}")
}

fn reduce_kernel(settings: &IcpSettings, intrinsics: &Intrinsics, pose: Pose) -> Kernel {
    Kernel::IcpReduce {
        pose,
        intrinsics: *intrinsics,
        max_distance: settings.max_distance,
        min_cos: settings.max_angle_degrees.to_radians().cos(),
    }
}

/// ICP with the CPU reference reduction.
pub fn register_cpu(
    source: &Cloud,
    model: &Cloud,
    intrinsics: &Intrinsics,
    settings: &IcpSettings,
    initial: Pose,
) -> Result<Registration, RegistrationError> {
    let min_cos = settings.max_angle_degrees.to_radians().cos();
    iterate(settings, initial, |pose| {
        Ok(icp::reduce(
            [&source.points, &source.normals, &model.points, &model.normals],
            pose,
            intrinsics,
            settings.max_distance,
            min_cos,
        ))
    })
}

/// ICP with the reduction on the GPU: the four clouds uploaded once per registration, each
/// iteration a new pose (uniform write), the reduction and a readback of the 29 sums.
pub struct GpuRegistration<'g> {
    pipeline: ChainRun<'g>,
    intrinsics: Intrinsics,
    settings: IcpSettings,
}

impl<'g> GpuRegistration<'g> {
    /// Buffers for clouds of `intrinsics`' size.
    pub fn new(
        gpu: &'g Gpu,
        intrinsics: &Intrinsics,
        settings: &IcpSettings,
    ) -> Result<GpuRegistration<'g>, ChainError> {
        let shape = Shape { width: intrinsics.width, height: intrinsics.height, planes: 3 };
        let mut pipeline = Pipeline::new();
        let inputs: Vec<_> = ["source", "source normals", "model", "model normals"]
            .iter()
            .map(|name| pipeline.source(name, shape))
            .collect();
        let sums = pipeline.step(reduce_kernel(settings, intrinsics, crate::camera::IDENTITY), &inputs)?[0];
        pipeline.sink(sums)?;
        Ok(GpuRegistration {
            pipeline: ChainRun::new(Some(gpu), &pipeline),
            intrinsics: *intrinsics,
            settings: *settings,
        })
    }

    pub fn register(
        &mut self,
        source: &Cloud,
        model: &Cloud,
        initial: Pose,
    ) -> Result<Registration, RegistrationError> {
        let (settings, intrinsics) = (self.settings, self.intrinsics);
        let mut first = true;
        let pipeline = &mut self.pipeline;
        iterate(&settings, initial, |pose| {
            pipeline
                .set_kernel(0, reduce_kernel(&settings, &intrinsics, *pose))
                .map_err(RegistrationError::Pipeline)?;
            let sums = if std::mem::take(&mut first) {
                let sources =
                    [source.points.clone(), source.normals.clone(), model.points.clone(), model.normals.clone()];
                pipeline.run(&sources)
            } else {
                pipeline.rerun()
            };
            let sums = sums.map_err(RegistrationError::Pipeline)?;
            Ok(std::array::from_fn(|k| sums[0].data[k] as f64))
        })
    }
}

/// Registered clouds merged in the model's frame (the "accumulation to model" of Table 6.2).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Accumulation {
    pub points: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
}

impl Accumulation {
    /// Adds every valid point of `cloud`, moved by `pose` into the model's frame.
    pub fn add(&mut self, cloud: &Cloud, pose: &Pose) {
        let (points, normals) = valid_points(&cloud.points, &cloud.normals);
        self.points.extend(points.into_iter().map(|p| apply(pose, p, true)));
        self.normals.extend(normals.into_iter().map(|n| apply(pose, n, false)));
    }

    /// Writes the points and normals as binary little-endian PLY.
    pub fn write_ply(&self, out: &mut impl Write) -> io::Result<()> {
        gudsl_formats::ply::write(out, &self.points, &self.normals, "gudsl-runtime accumulated ToF point cloud")
    }
}

/// The valid points of a cloud's 3-plane images (z ≠ 0) and their normals.
pub fn valid_points(points: &Image, normals: &Image) -> gudsl_formats::ply::Points {
    (0..points.pixels()).filter(|&i| points.vector(i)[2] != 0.0).map(|i| (points.vector(i), normals.vector(i))).unzip()
}

/// Registers each cloud against the one before (frame to frame) and chains the increments into
/// absolute poses in the first cloud's frame (sec. 6.5.3: identity for the first frame).
pub fn track(
    clouds: &[Cloud],
    mut register: impl FnMut(&Cloud, &Cloud, Pose) -> Result<Registration, RegistrationError>,
) -> Result<Vec<Pose>, RegistrationError> {
    let mut poses = vec![crate::camera::IDENTITY];
    let mut increment = crate::camera::IDENTITY;
    for pair in clouds.windows(2) {
        // The previous increment is the guess for this one (constant motion).
        increment = register(&pair[1], &pair[0], increment)?.pose;
        poses.push(compose(poses.last().expect("the first pose"), &increment));
    }
    Ok(poses)
}
