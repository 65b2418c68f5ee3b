//! ROS 2 messages as rosbag2 records them: `sensor_msgs/msg/Image` and
//! `sensor_msgs/msg/PointCloud2`, in CDR (through `cdr-encoding`: the 4-byte encapsulation
//! header, then the fields little- or big-endian as it says), with the `ros2msg` schema texts
//! Foxglove, Rerun and the Python `mcap-ros2-support` decoder know them by.

use byteorder::{BigEndian, LittleEndian};
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// A message that cannot be read: what is wrong with it.
pub type MessageError = String;

/// `builtin_interfaces/Time`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// The time `nanoseconds` after the epoch (the seconds saturate past 2038).
    pub fn from_nanos(nanoseconds: u64) -> Time {
        let sec = i32::try_from(nanoseconds / 1_000_000_000).unwrap_or(i32::MAX);
        Time { sec, nanosec: (nanoseconds % 1_000_000_000) as u32 }
    }
}

/// `std_msgs/Header`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}

/// `sensor_msgs/msg/Image`: `height` rows of `step` bytes, each `width` pixels of `encoding`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Image {
    pub header: Header,
    pub height: u32,
    pub width: u32,
    pub encoding: String,
    pub is_bigendian: u8,
    pub step: u32,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
}

/// `sensor_msgs/msg/PointField`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PointField {
    pub name: String,
    pub offset: u32,
    pub datatype: u8,
    pub count: u32,
}

/// `sensor_msgs/msg/PointCloud2`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PointCloud2 {
    pub header: Header,
    pub height: u32,
    pub width: u32,
    pub fields: Vec<PointField>,
    pub is_bigendian: bool,
    pub point_step: u32,
    pub row_step: u32,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
    pub is_dense: bool,
}

/// `PointField`'s datatypes of 32- and 64-bit floats.
const FLOAT32: u8 = 7;
const FLOAT64: u8 = 8;

/// The schema name and `ros2msg` text of `sensor_msgs/msg/Image`.
pub const IMAGE_SCHEMA: (&str, &str) = (
    "sensor_msgs/msg/Image",
    concat!(
        "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n",
        "uint32 step\nuint8[] data\n",
        "================================================================================\n",
        "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n",
        "================================================================================\n",
        "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
    ),
);

/// The schema name and `ros2msg` text of `sensor_msgs/msg/PointCloud2`.
pub const POINT_CLOUD_SCHEMA: (&str, &str) = (
    "sensor_msgs/msg/PointCloud2",
    concat!(
        "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\n",
        "bool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
        "================================================================================\n",
        "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n",
        "================================================================================\n",
        "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n",
        "================================================================================\n",
        "MSG: sensor_msgs/PointField\nuint8 INT8    = 1\nuint8 UINT8   = 2\nuint8 INT16   = 3\n",
        "uint8 UINT16  = 4\nuint8 INT32   = 5\nuint8 UINT32  = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\n",
        "string name\nuint32 offset\nuint8  datatype\nuint32 count\n"
    ),
);

/// `message` in CDR, little-endian, after its encapsulation header.
pub fn encode<T: Serialize>(message: &T) -> Vec<u8> {
    let body = cdr_encoding::to_vec::<T, LittleEndian>(message).expect("a message of plain fields always encodes");
    [&[0, 1, 0, 0][..], &body].concat()
}

/// The message in `bytes` (CDR or PL_CDR, either byte order, as its header says).
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, MessageError> {
    let (header, body) = bytes.split_first_chunk::<4>().ok_or("is shorter than a CDR header")?;
    let decoded = match header[1] {
        0 | 2 => cdr_encoding::from_bytes::<T, BigEndian>(body),
        1 | 3 => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        other => return Err(format!("has CDR representation {other}, not plain CDR")),
    };
    decoded.map(|(message, _)| message).map_err(|e| format!("is not a well-formed message ({e})"))
}

/// How a pixel of an image encoding is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pixel {
    U8,
    U16,
    I16,
    I32,
    F32,
    F64,
}

impl Pixel {
    /// The one-channel encodings (REP 118 depth: `16UC1` millimetres, `32FC1` metres).
    fn of(encoding: &str) -> Option<Pixel> {
        Some(match encoding {
            "mono8" | "8UC1" => Pixel::U8,
            "mono16" | "16UC1" => Pixel::U16,
            "16SC1" => Pixel::I16,
            "32SC1" => Pixel::I32,
            "32FC1" => Pixel::F32,
            "64FC1" => Pixel::F64,
            _ => return None,
        })
    }

    fn bytes(self) -> usize {
        match self {
            Pixel::U8 => 1,
            Pixel::U16 | Pixel::I16 => 2,
            Pixel::I32 | Pixel::F32 => 4,
            Pixel::F64 => 8,
        }
    }

    /// The value of one pixel's bytes.
    fn value(self, bytes: &[u8], big: bool) -> f32 {
        macro_rules! read {
            ($t:ty) => {{
                let array = bytes.try_into().expect("a pixel's bytes");
                if big {
                    <$t>::from_be_bytes(array) as f32
                } else {
                    <$t>::from_le_bytes(array) as f32
                }
            }};
        }
        match self {
            Pixel::U8 => bytes[0] as f32,
            Pixel::U16 => read!(u16),
            Pixel::I16 => read!(i16),
            Pixel::I32 => read!(i32),
            Pixel::F32 => read!(f32),
            Pixel::F64 => read!(f64),
        }
    }
}

/// The encodings [`Image::values`] reads.
pub const ONE_CHANNEL_ENCODINGS: &str = "mono8, 8UC1, mono16, 16UC1, 16SC1, 32SC1, 32FC1 or 64FC1";

impl Image {
    /// A one-channel image of 32-bit floats (`32FC1`, REP 118's depth in metres).
    pub fn floats(header: Header, width: usize, height: usize, values: &[f32]) -> Image {
        Image {
            header,
            height: height as u32,
            width: width as u32,
            encoding: "32FC1".to_string(),
            is_bigendian: 0,
            step: 4 * width as u32,
            data: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    /// A one-channel image of 16-bit values (`16UC1`), when every value is a whole number in
    /// 0..=65535 (a camera's raw channels); `None` otherwise.
    pub fn sixteen_bits(header: Header, width: usize, height: usize, values: &[f32]) -> Option<Image> {
        let whole = |v: &f32| (0.0..=65535.0).contains(v) && v.fract() == 0.0;
        values.iter().all(whole).then(|| Image {
            header,
            height: height as u32,
            width: width as u32,
            encoding: "16UC1".to_string(),
            is_bigendian: 0,
            step: 2 * width as u32,
            data: values.iter().flat_map(|&v| (v as u16).to_le_bytes()).collect(),
        })
    }

    /// Whether its encoding is integers (a depth image of them is in millimetres or so).
    pub fn is_integer(&self) -> Result<bool, MessageError> {
        Ok(!matches!(self.pixel()?, Pixel::F32 | Pixel::F64))
    }

    fn pixel(&self) -> Result<Pixel, MessageError> {
        Pixel::of(&self.encoding)
            .ok_or_else(|| format!("has encoding `{}`; expected one channel: {ONE_CHANNEL_ENCODINGS}", self.encoding))
    }

    /// Its pixels' values, row by row, checked against the sizes it claims.
    pub fn values(&self) -> Result<Vec<f32>, MessageError> {
        let pixel = self.pixel()?;
        let (width, height, step) = (self.width as usize, self.height as usize, self.step as usize);
        let row = width * pixel.bytes();
        if step < row || self.data.len() < step.saturating_mul(height) {
            return Err(format!(
                "is {width}×{height} {} with rows of {step} bytes but holds {} bytes",
                self.encoding,
                self.data.len()
            ));
        }
        let big = self.is_bigendian != 0;
        let mut values = Vec::with_capacity(width * height);
        for y in 0..height {
            let bytes = &self.data[y * step..y * step + row];
            values.extend(bytes.chunks_exact(pixel.bytes()).map(|p| pixel.value(p, big)));
        }
        Ok(values)
    }
}

impl PointCloud2 {
    /// An unorganized cloud of points with normals: fields `x y z normal_x normal_y normal_z`,
    /// 32-bit floats (PCL's `PointNormal` names, which Foxglove and RViz show).
    pub fn with_normals(header: Header, points: &[[f32; 3]], normals: &[[f32; 3]]) -> PointCloud2 {
        let names = ["x", "y", "z", "normal_x", "normal_y", "normal_z"];
        let fields = names
            .iter()
            .enumerate()
            .map(|(k, name)| PointField { name: name.to_string(), offset: 4 * k as u32, datatype: FLOAT32, count: 1 })
            .collect();
        let data = points.iter().zip(normals).flat_map(|(p, n)| p.iter().chain(n).flat_map(|v| v.to_le_bytes()));
        PointCloud2 {
            header,
            height: 1,
            width: points.len() as u32,
            fields,
            is_bigendian: false,
            point_step: 24,
            row_step: 24 * points.len() as u32,
            data: data.collect(),
            is_dense: true,
        }
    }
}

impl PointCloud2 {
    /// Its points and normals (`normal_x normal_y normal_z` when it has them, else zero),
    /// points with a NaN coordinate left out; checked against the sizes it claims.
    pub fn points(&self) -> Result<crate::ply::Points, MessageError> {
        let field = |name: &str| {
            self.fields
                .iter()
                .find(|f| f.name == name && f.count <= 1 && (f.datatype == FLOAT32 || f.datatype == FLOAT64))
        };
        let [x, y, z] = ["x", "y", "z"].map(field);
        let (Some(x), Some(y), Some(z)) = (x, y, z) else {
            return Err("has no fields x, y and z of floats".to_string());
        };
        let normal = ["normal_x", "normal_y", "normal_z"].map(field);
        let (step, row) = (self.point_step as usize, self.row_step as usize);
        let (width, height) = (self.width as usize, self.height as usize);
        let fits = |f: &PointField| f.offset as usize + if f.datatype == FLOAT32 { 4 } else { 8 } <= step;
        let all = [x, y, z].into_iter().chain(normal.into_iter().flatten());
        if !all.clone().all(fits) || row < width.saturating_mul(step) || self.data.len() < row.saturating_mul(height) {
            return Err(format!(
                "is {width}×{height} points of {step} bytes in rows of {row} bytes but holds {} bytes",
                self.data.len()
            ));
        }
        let big = self.is_bigendian;
        let read = |point: &[u8], f: &PointField| {
            let at = f.offset as usize;
            match f.datatype {
                FLOAT32 => Pixel::F32.value(&point[at..at + 4], big),
                _ => Pixel::F64.value(&point[at..at + 8], big),
            }
        };
        let (mut points, mut normals) = (Vec::new(), Vec::new());
        for r in 0..height {
            for point in self.data[r * row..r * row + width * step].chunks_exact(step.max(1)).take(width) {
                let p = [x, y, z].map(|f| read(point, f));
                if p.iter().any(|v| v.is_nan()) {
                    continue;
                }
                points.push(p);
                normals.push(normal.map(|f| f.map_or(0.0, |f| read(point, f))));
            }
        }
        Ok((points, normals))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_go_round_in_either_byte_order() {
        let header = Header { stamp: Time::from_nanos(1_500_000_000), frame_id: "tof".into() };
        let image = Image::floats(header, 3, 2, &[0.5, 1.0, 1.5, 2.0, 2.5, 3.0]);
        let bytes = encode(&image);
        assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
        let back: Image = decode(&bytes).unwrap();
        assert_eq!(back, image);
        assert_eq!(back.header.stamp, Time { sec: 1, nanosec: 500_000_000 });
        assert_eq!(back.values().unwrap(), vec![0.5, 1.0, 1.5, 2.0, 2.5, 3.0]);

        let body = cdr_encoding::to_vec::<Image, BigEndian>(&image).unwrap();
        let big: Image = decode(&[&[0, 0, 0, 0][..], &body].concat()).unwrap();
        assert_eq!(big.width, 3);
    }

    #[test]
    fn sixteen_bit_rows_with_padding_and_big_endian_pixels_are_read() {
        let image = Image {
            height: 2,
            width: 2,
            encoding: "16UC1".into(),
            is_bigendian: 1,
            step: 6,
            data: vec![0, 1, 1, 0, 9, 9, 0xff, 0xff, 0, 2, 9, 9],
            ..Image::default()
        };
        assert_eq!(image.values().unwrap(), vec![1.0, 256.0, 65535.0, 2.0]);
        assert!(image.is_integer().unwrap());
        let whole = Image::sixteen_bits(Header::default(), 2, 1, &[0.0, 65535.0]).unwrap();
        assert_eq!(whole.values().unwrap(), vec![0.0, 65535.0]);
        assert!(Image::sixteen_bits(Header::default(), 1, 1, &[0.5]).is_none());
        assert!(Image::sixteen_bits(Header::default(), 1, 1, &[65536.0]).is_none());
    }

    #[test]
    fn images_that_lie_about_their_size_or_encoding_are_refused() {
        let short = Image { height: 100, width: 100, encoding: "32FC1".into(), step: 400, ..Image::default() };
        assert!(short.values().unwrap_err().contains("holds 0 bytes"), "{:?}", short.values());
        let colour = Image { encoding: "rgb8".into(), ..Image::default() };
        assert!(colour.values().unwrap_err().contains("expected one channel"));
        assert!(decode::<Image>(&[0, 1]).unwrap_err().contains("shorter"));
        assert!(decode::<Image>(&[0, 1, 0, 0, 5]).unwrap_err().contains("not a well-formed"));
    }

    #[test]
    fn clouds_hold_points_then_normals() {
        let cloud = PointCloud2::with_normals(Header::default(), &[[1.0, 2.0, 3.0]], &[[0.0, 0.0, 1.0]]);
        let back: PointCloud2 = decode(&encode(&cloud)).unwrap();
        assert_eq!(back, cloud);
        assert_eq!(back.data.len(), 24);
        assert_eq!(f32::from_le_bytes(back.data[8..12].try_into().unwrap()), 3.0);
        assert_eq!(back.fields[3].name, "normal_x");
        assert_eq!(back.points().unwrap(), (vec![[1.0, 2.0, 3.0]], vec![[0.0, 0.0, 1.0]]));
    }

    #[test]
    fn clouds_of_other_layouts_are_read_and_lying_ones_refused() {
        // x y z as float64 with padding, no normals, a NaN point (not dense), two rows.
        let field = |name: &str, offset| PointField { name: name.into(), offset, datatype: FLOAT64, count: 1 };
        let mut data = Vec::new();
        for p in [[1.0f64, 2.0, 3.0], [f64::NAN, 0.0, 0.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]] {
            p.iter().for_each(|v| data.extend(v.to_le_bytes()));
            data.extend([0; 8]);
        }
        let cloud = PointCloud2 {
            height: 2,
            width: 2,
            fields: vec![field("x", 0), field("y", 8), field("z", 16)],
            point_step: 32,
            row_step: 64,
            data,
            ..PointCloud2::default()
        };
        let (points, normals) = cloud.points().unwrap();
        assert_eq!(points, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]);
        assert_eq!(normals, vec![[0.0; 3]; 3]);
        let short = PointCloud2 { height: 1000, ..cloud.clone() };
        assert!(short.points().unwrap_err().contains("holds 128 bytes"));
        let outside = PointCloud2 { point_step: 16, row_step: 32, ..cloud };
        assert!(outside.points().is_err(), "z at 16 does not fit a point of 16 bytes");
    }
}
