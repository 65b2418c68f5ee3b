//! Point clouds as PCD files (PCL's format), through `pcd-rs`: written as binary
//! `x y z normal_x normal_y normal_z` floats (PCL's `PointNormal`); read from any PCD 0.7 with
//! `x y z` fields (normals when it has them; ASCII, binary or compressed), after its header's
//! point count and sizes are checked against what the file holds — the crate itself trusts
//! them (a compressed file claiming more than it holds would allocate or index past its data).

use std::{
    io::{Cursor, Read},
    path::Path,
};

use gudsl_files::Folder;
use pcd_rs::{DataKind, DynReader, DynRecord, DynWriter, Field, PcdMeta, Schema, ValueKind, WriterInit};

use crate::ply::Points;

/// The longest PCD file read (1 GiB).
pub const MAX_PCD_BYTES: u64 = 1 << 30;

/// Why a cloud cannot be read: the file and what is wrong, said of it.
pub type PcdError = String;

/// The fields a cloud is written with.
const FIELDS: [&str; 6] = ["x", "y", "z", "normal_x", "normal_y", "normal_z"];

/// `points` and their `normals` as a binary PCD file.
pub fn encode(points: &[[f32; 3]], normals: &[[f32; 3]]) -> Vec<u8> {
    let schema = Schema::from_iter(FIELDS.map(|name| (name, ValueKind::F32, 1)));
    let init = WriterInit {
        width: points.len() as u64,
        height: 1,
        viewpoint: Default::default(),
        data_kind: DataKind::Binary,
        schema: Some(schema),
        version: None,
    };
    let mut bytes = Cursor::new(Vec::new());
    let mut writer: DynWriter<_> = init.build_from_writer(&mut bytes).expect("a PCD header always writes to memory");
    for (p, n) in points.iter().zip(normals) {
        let record = DynRecord([p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| Field::F32(vec![v])).to_vec());
        writer.push(&record).expect("a record of the schema always writes to memory");
    }
    writer.finish().expect("a PCD file always finishes in memory");
    bytes.into_inner()
}

/// The cloud in the PCD file at `path` beneath `folder`.
pub fn read(folder: &Folder, path: &Path) -> Result<Points, PcdError> {
    let bytes = folder.read(path, MAX_PCD_BYTES).map_err(|e| e.to_string())?;
    read_bytes(&bytes, path)
}

/// The cloud in `bytes`, read as the file `path` would be: what the fuzz target feeds.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<Points, PcdError> {
    let failed = |e: &dyn std::fmt::Display| format!("{}: is not a readable PCD file ({e})", path.display());
    let mut header = Cursor::new(bytes);
    let meta = PcdMeta::from_reader(&mut header).map_err(|e| failed(&e))?;
    let data = &bytes[header.position() as usize..];
    holds_what_it_claims(&meta, data).map_err(|e| format!("{}: {e}", path.display()))?;
    let [x, y, z] = ["x", "y", "z"].map(|name| field(&meta, name));
    let (Some(x), Some(y), Some(z)) = (x, y, z) else {
        return Err(format!("{}: has no fields x, y and z of one float each", path.display()));
    };
    let normal = ["normal_x", "normal_y", "normal_z"].map(|name| field(&meta, name));
    let reader = DynReader::from_reader(Cursor::new(bytes)).map_err(|e| failed(&e))?;
    let (mut points, mut normals) = (Vec::new(), Vec::new());
    for record in reader {
        let record = record.map_err(|e| failed(&e))?;
        points.push([x, y, z].map(|k| value(&record, k)));
        normals.push(normal.map(|k| k.map_or(0.0, |k| value(&record, k))));
    }
    Ok((points, normals))
}

/// An error unless the data after the header holds the points the header claims.
fn holds_what_it_claims(meta: &PcdMeta, data: &[u8]) -> Result<(), String> {
    let record: u64 = meta.field_defs.iter().map(|f| f.kind_bytes() * f.count).sum();
    let wanted = meta.num_points.checked_mul(record).filter(|&n| n <= MAX_PCD_BYTES << 4);
    let wanted = wanted.ok_or_else(|| format!("claims {} points of {record} bytes: too many", meta.num_points))?;
    let claims =
        |held: u64| format!("claims {} points ({wanted} bytes) but holds {held} bytes of data", meta.num_points);
    match meta.data {
        DataKind::Binary if (data.len() as u64) < wanted => Err(claims(data.len() as u64)),
        DataKind::BinaryCompressed => {
            let mut sizes = [0u8; 8];
            Cursor::new(data).read_exact(&mut sizes).map_err(|_| claims(data.len() as u64))?;
            let compressed = u64::from(u32::from_le_bytes(sizes[..4].try_into().expect("4 bytes")));
            let uncompressed = u64::from(u32::from_le_bytes(sizes[4..].try_into().expect("4 bytes")));
            if compressed > data.len() as u64 - 8 || uncompressed != wanted {
                return Err(format!(
                    "claims {} points ({wanted} bytes) compressed from {uncompressed} into {compressed} bytes, but holds {} bytes of data",
                    meta.num_points,
                    data.len() - 8
                ));
            }
            Ok(())
        }
        // An ASCII point takes a character and a separator a value at least.
        DataKind::Ascii if (data.len() as u64) < meta.num_points.saturating_mul(2) => Err(claims(data.len() as u64)),
        _ => Ok(()),
    }
}

/// The index of the field `name` when it is one float.
fn field(meta: &PcdMeta, name: &str) -> Option<usize> {
    meta.field_defs
        .iter()
        .position(|f| f.name == name && f.count == 1 && matches!(f.kind, ValueKind::F32 | ValueKind::F64))
}

fn value(record: &DynRecord, index: usize) -> f32 {
    match &record.0[index] {
        Field::F32(v) => v[0],
        Field::F64(v) => v[0] as f32,
        _ => f32::NAN,
    }
}

/// Bytes of a value of a field's kind.
trait KindBytes {
    fn kind_bytes(&self) -> u64;
}

impl KindBytes for pcd_rs::FieldDef {
    fn kind_bytes(&self) -> u64 {
        match self.kind {
            ValueKind::U8 | ValueKind::I8 => 1,
            ValueKind::U16 | ValueKind::I16 => 2,
            ValueKind::U32 | ValueKind::I32 | ValueKind::F32 => 4,
            ValueKind::U64 | ValueKind::I64 | ValueKind::F64 => 8,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clouds_go_round_and_ascii_files_of_points_alone_are_read() {
        let bytes = encode(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.5]], &[[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]);
        let text = String::from_utf8_lossy(&bytes[..120]).into_owned();
        assert!(text.contains("FIELDS x y z normal_x normal_y normal_z"), "{text}");
        let (points, normals) = read_bytes(&bytes, Path::new("c.pcd")).unwrap();
        assert_eq!(points, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.5]]);
        assert_eq!(normals[1], [0.0, 1.0, 0.0]);

        let ascii = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n0.5 1.5 2.5\n";
        let (points, normals) = read_bytes(ascii.as_bytes(), Path::new("a.pcd")).unwrap();
        assert_eq!((points, normals), (vec![[0.5, 1.5, 2.5]], vec![[0.0; 3]]));
    }

    #[test]
    fn headers_claiming_more_than_the_file_holds_are_refused_unread() {
        let bytes = encode(&[[1.0, 2.0, 3.0]], &[[0.0, 0.0, 1.0]]);
        let text = String::from_utf8_lossy(&bytes)
            .replace("POINTS 1", "POINTS 900000000")
            .replace("WIDTH 1", "WIDTH 900000000");
        let error = read_bytes(text.as_bytes(), Path::new("big.pcd")).unwrap_err();
        assert!(error.contains("big.pcd: claims 900000000 points"), "{error}");
        let compressed = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary_compressed\n";
        let sizes = [4u32.to_le_bytes(), 0x7fff_ffffu32.to_le_bytes()].concat();
        let compressed = [compressed.as_bytes(), &sizes, &[0; 4]].concat();
        let error = read_bytes(&compressed, Path::new("z.pcd")).unwrap_err();
        assert!(error.contains("compressed from"), "{error}");
        let error = read_bytes(b"not a pcd", Path::new("n.pcd")).unwrap_err();
        assert!(error.contains("n.pcd: is not a readable PCD file"), "{error}");
    }
}
