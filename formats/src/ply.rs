//! Point clouds with normals as PLY files, through `ply-rs-bw`: written as binary little-endian
//! `x y z nx ny nz` floats (what MeshLab and CloudCompare open), read back from any PLY with
//! those vertex properties (ASCII or binary).

use std::io::{self, BufRead, Write};

use ply_rs_bw::{
    parser::Parser,
    ply::{
        Addable, ElementDef, Encoding, Ply, Property, PropertyAccess, PropertyAccessResult, PropertyDef, PropertyType,
        ScalarType,
    },
    writer::Writer,
};

/// One vertex: a point and its normal.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Vertex {
    point: [f32; 3],
    normal: [f32; 3],
}

const NAMES: [&str; 6] = ["x", "y", "z", "nx", "ny", "nz"];

impl PropertyAccess for Vertex {
    fn new() -> Vertex {
        Vertex::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let value = match property {
            Property::Float(v) => v,
            Property::Double(v) => v as f32,
            _ => return PropertyAccessResult::Ignored,
        };
        match NAMES.iter().position(|n| *n == name) {
            Some(k @ 0..=2) => self.point[k] = value,
            Some(k) => self.normal[k - 3] = value,
            None => return PropertyAccessResult::Ignored,
        }
        PropertyAccessResult::Set
    }

    fn get_float(&self, name: &str) -> Option<f32> {
        match NAMES.iter().position(|n| *n == name)? {
            k @ 0..=2 => Some(self.point[k]),
            k => Some(self.normal[k - 3]),
        }
    }
}

/// Writes `points` and their `normals` as a binary little-endian PLY.
pub fn write(out: &mut impl Write, points: &[[f32; 3]], normals: &[[f32; 3]], comment: &str) -> io::Result<()> {
    let mut ply = Ply::<Vertex>::new();
    ply.header.encoding = Encoding::BinaryLittleEndian;
    ply.header.comments.push(comment.to_string());
    let mut vertex = ElementDef::new("vertex".to_string());
    for name in NAMES {
        vertex.properties.add(PropertyDef::new(name.to_string(), PropertyType::Scalar(ScalarType::Float)));
    }
    ply.header.elements.add(vertex);
    let vertices = points.iter().zip(normals).map(|(&point, &normal)| Vertex { point, normal }).collect();
    ply.payload.insert("vertex".to_string(), vertices);
    Writer::new().write_ply(out, &mut ply)?;
    Ok(())
}

/// Points and their normals.
pub type Points = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// The points and normals of a PLY's vertices (normals zero where it has none).
pub fn read(input: &mut impl BufRead) -> io::Result<Points> {
    let ply = Parser::<Vertex>::new().read_ply(input)?;
    let vertices = ply.payload.get("vertex").map_or(&[][..], Vec::as_slice);
    Ok(vertices.iter().map(|v| (v.point, v.normal)).unzip())
}

#[cfg(test)]
mod tests {
    #[test]
    fn clouds_round_trip_and_ascii_files_are_read() {
        let points = vec![[1.0, 2.0, 3.5], [-0.25, 0.0, 4.0]];
        let normals = vec![[0.0, 0.0, -1.0], [0.6, 0.0, -0.8]];
        let mut bytes = Vec::new();
        super::write(&mut bytes, &points, &normals, "test").unwrap();
        let header = String::from_utf8_lossy(&bytes[..bytes.windows(10).position(|w| w == b"end_header").unwrap()]);
        assert!(header.contains("format binary_little_endian 1.0") && header.contains("element vertex 2"), "{header}");
        assert_eq!(super::read(&mut &bytes[..]).unwrap(), (points, normals));
        let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
        assert_eq!(super::read(&mut ascii.as_bytes()).unwrap(), (vec![[1.0, 2.0, 3.0]], vec![[0.0; 3]]));
    }
}
