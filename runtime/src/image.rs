//! Images on the CPU: `planes` planes of `width × height` f32 samples, row-major, plane after
//! plane (a raw PMD frame is 8 planes: A and B channels of the four phase images).

/// Size of an image: `planes` planes of `width × height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shape {
    pub width: usize,
    pub height: usize,
    pub planes: usize,
}

impl Shape {
    pub fn len(&self) -> usize {
        self.width * self.height * self.planes
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A stack of equally sized f32 planes.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub planes: usize,
    pub data: Vec<f32>,
}

impl Image {
    /// An image of zeros.
    pub fn zeros(width: usize, height: usize, planes: usize) -> Image {
        Image { width, height, planes, data: vec![0.0; width * height * planes] }
    }

    /// One plane from its samples (`data.len()` must be `width * height`).
    pub fn from_plane(width: usize, height: usize, data: Vec<f32>) -> Image {
        assert_eq!(data.len(), width * height, "a {width}×{height} plane needs {} samples", width * height);
        Image { width, height, planes: 1, data }
    }

    /// Samples per plane.
    pub fn pixels(&self) -> usize {
        self.width * self.height
    }

    /// Plane `p`.
    pub fn plane(&self, p: usize) -> &[f32] {
        &self.data[p * self.pixels()..(p + 1) * self.pixels()]
    }

    /// Plane `p`, mutable.
    pub fn plane_mut(&mut self, p: usize) -> &mut [f32] {
        let n = self.pixels();
        &mut self.data[p * n..(p + 1) * n]
    }

    /// The vector of a 3-plane image (points, normals, rays) at pixel `i`.
    pub fn vector(&self, i: usize) -> [f32; 3] {
        let n = self.pixels();
        [self.data[i], self.data[n + i], self.data[2 * n + i]]
    }

    /// The sample at `(x, y)` of plane `p`, coordinates clamped to the image (edge replication).
    pub fn at_clamped(&self, p: usize, x: isize, y: isize) -> f32 {
        let x = x.clamp(0, self.width as isize - 1) as usize;
        let y = y.clamp(0, self.height as isize - 1) as usize;
        self.data[p * self.pixels() + y * self.width + x]
    }
}
