//! Point clouds with normals as PLY files, through `ply-rs-bw`: written as binary little-endian
//! `x y z nx ny nz` floats (what MeshLab and CloudCompare open), read back from any PLY with
//! those vertex properties (ASCII or binary).

use std::io::{self, Write};

use ply_rs_bw::{
    parser::{Parser, Reader},
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

/// The points and normals of a PLY's vertices (normals zero where it has none), from the file's
/// `bytes`. A header whose elements could not fit in the bytes (at the fewest bytes each of
/// their properties takes) is refused before any element is read: an element of no properties
/// counted in billions made the parser allocate gigabytes (found by the fuzz target `ply`).
pub fn read(bytes: &[u8]) -> io::Result<Points> {
    let parser = Parser::<Vertex>::new();
    let header = parser.read_header(&mut Reader::new(bytes))?;
    let claimed = header.elements.values().try_fold(0u64, |total, element| {
        let least = least_bytes(&header.encoding, element);
        (element.count as u64).checked_mul(least).and_then(|bytes| total.checked_add(bytes))
    });
    match claimed {
        Some(claimed) if claimed <= bytes.len() as u64 => {}
        _ => {
            let counts: Vec<String> = header.elements.values().map(|e| format!("{} {}", e.count, e.name)).collect();
            let message = format!("its header claims {} in {} bytes", counts.join(", "), bytes.len());
            return Err(io::Error::new(io::ErrorKind::InvalidData, message));
        }
    }
    let ply = parser.read_ply(&mut &bytes[..])?;
    let vertices = ply.payload.get("vertex").map_or(&[][..], Vec::as_slice);
    Ok(vertices.iter().map(|v| (v.point, v.normal)).unzip())
}

/// The fewest bytes one `element` takes in a file: its scalars' sizes (a list's count) in
/// binary, a digit and a separator a property in ASCII; at least one.
fn least_bytes(encoding: &Encoding, element: &ElementDef) -> u64 {
    let properties = element.properties.values();
    let bytes: u64 = match encoding {
        Encoding::Ascii => 2 * properties.count() as u64,
        _ => properties
            .map(|p| match &p.data_type {
                PropertyType::Scalar(scalar) | PropertyType::List(scalar, _) => scalar_bytes(scalar),
            })
            .sum(),
    };
    bytes.max(1)
}

fn scalar_bytes(scalar: &ScalarType) -> u64 {
    match scalar {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
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
        assert_eq!(super::read(&bytes).unwrap(), (points, normals));
        let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
        assert_eq!(super::read(ascii.as_bytes()).unwrap(), (vec![[1.0, 2.0, 3.0]], vec![[0.0; 3]]));
    }

    #[test]
    fn a_header_claiming_more_elements_than_the_file_holds_is_refused_unread() {
        // Found by the fuzz target `ply`: 333 333 313 elements of no properties in 271 bytes
        // (the parser allocated 4 GB for them).
        let found = include_bytes!("../../fuzz/corpus/ply/element_of_no_properties_counted_in_billions.ply");
        let error = super::read(found).unwrap_err();
        assert!(error.to_string().contains("claims 333333313 vervex"), "{error}");
        let binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\n";
        assert!(super::read(binary).unwrap_err().to_string().contains("claims 1000 vertex in"));
    }
}
