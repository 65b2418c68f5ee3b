//! OpenEXR depth images, through the `exr` crate: read — the first layer's depth channel (`Z`,
//! `depth`, `Y` or `R`, or its only channel), any sample type, its size checked against the
//! pixel cap from the header before anything is decoded — and written, float32 channels of
//! one layer, lossless.

use std::{
    io::{BufRead, BufReader, Cursor, Seek},
    path::Path,
};

use exr::prelude::{
    read, AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, MetaData, ReadChannels,
    ReadLayers, Vec2, WritableImage,
};
use gudsl_files::Folder;

use crate::picture::{PictureError, MAX_PICTURE_FILE_BYTES, MAX_PICTURE_PIXELS};

/// The channels taken as depth, in order of preference.
const DEPTH_CHANNELS: [&str; 4] = ["Z", "depth", "Y", "R"];

/// A depth image's width and height, from the file's header.
pub fn dimensions(folder: &Folder, path: &Path) -> Result<(usize, usize), PictureError> {
    size_checked(opened(folder, path)?, path)
}

/// The depth channel of the file at `path` beneath `folder`: width, height, values row by row.
pub fn read_depth(folder: &Folder, path: &Path) -> Result<(usize, usize, Vec<f32>), PictureError> {
    let mut source = opened(folder, path)?;
    size_checked(&mut source, path)?;
    source.rewind().map_err(|e| format!("{}: {e}", path.display()))?;
    depth_of(source, path)
}

/// The depth channel in `bytes`, read as the file `path` would be: what the fuzz target feeds.
pub fn read_depth_bytes(bytes: &[u8], path: &Path) -> Result<(usize, usize, Vec<f32>), PictureError> {
    size_checked(Cursor::new(bytes), path)?;
    depth_of(Cursor::new(bytes), path)
}

/// An EXR file of one layer of float32 `channels` (name, values row by row), each
/// `width`×`height`.
pub fn encode(width: usize, height: usize, channels: &[(&str, &[f32])]) -> Vec<u8> {
    let list = channels.iter().map(|(name, values)| AnyChannel::new(*name, FlatSamples::F32(values.to_vec())));
    let layer = Layer::new(
        (width, height),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list.collect()),
    );
    let mut bytes = Cursor::new(Vec::new());
    Image::from_layer(layer).write().to_buffered(&mut bytes).expect("float channels of one size always encode");
    bytes.into_inner()
}

fn opened(folder: &Folder, path: &Path) -> Result<BufReader<std::fs::File>, PictureError> {
    let opened = folder.open_file(path, MAX_PICTURE_FILE_BYTES).map_err(|e| e.to_string())?;
    Ok(BufReader::new(opened.file))
}

/// The first layer's size from the header, refused above the pixel cap.
fn size_checked(source: impl BufRead + Seek, path: &Path) -> Result<(usize, usize), PictureError> {
    let meta = MetaData::read_from_buffered(source, false).map_err(|e| unreadable(path, e))?;
    let header = meta.headers.first().ok_or_else(|| format!("{}: holds no image", path.display()))?;
    let Vec2(width, height) = header.layer_size;
    if (width as u64) * (height as u64) > MAX_PICTURE_PIXELS || header.deep {
        return Err(format!(
            "{}: is {width}×{height}{}; at most {MAX_PICTURE_PIXELS} pixels of flat data are read",
            path.display(),
            if header.deep { " deep data" } else { "" }
        ));
    }
    Ok((width, height))
}

fn depth_of(source: impl BufRead + Seek, path: &Path) -> Result<(usize, usize, Vec<f32>), PictureError> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(source)
        .map_err(|e| unreadable(path, e))?;
    let layer = image.layer_data;
    let channels = &layer.channel_data.list;
    let named = |name: &str| channels.iter().find(|c| c.name.eq_case_insensitive(name));
    let chosen = DEPTH_CHANNELS.iter().find_map(|n| named(n)).or(match &channels[..] {
        [only] => Some(only),
        _ => None,
    });
    let Some(channel) = chosen else {
        let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
        return Err(format!(
            "{}: has channels {}; expected a depth channel (Z, depth, Y or R) or one channel",
            path.display(),
            names.join(", ")
        ));
    };
    let Vec2(width, height) = layer.size;
    Ok((width, height, channel.sample_data.values_as_f32().collect()))
}

fn unreadable(path: &Path, error: exr::error::Error) -> PictureError {
    format!("{}: is not a readable OpenEXR image ({error})", path.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_goes_round_and_the_depth_channel_is_chosen_by_name() {
        let bytes = encode(3, 2, &[("Z", &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5]), ("amplitude", &[9.0; 6])]);
        let (width, height, values) = read_depth_bytes(&bytes, Path::new("d.exr")).unwrap();
        assert_eq!((width, height), (3, 2));
        assert_eq!(values, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.5]);
        let only = encode(2, 1, &[("distance", &[0.5, 0.25])]);
        assert_eq!(read_depth_bytes(&only, Path::new("o.exr")).unwrap().2, vec![0.5, 0.25]);
    }

    #[test]
    fn files_without_a_depth_channel_or_not_exr_are_refused_by_name() {
        let two = encode(1, 1, &[("a", &[1.0]), ("b", &[2.0])]);
        let error = read_depth_bytes(&two, Path::new("two.exr")).unwrap_err();
        assert!(error.contains("two.exr: has channels a, b; expected a depth channel"), "{error}");
        let error = read_depth_bytes(b"not an exr", Path::new("x.exr")).unwrap_err();
        assert!(error.contains("x.exr: is not a readable OpenEXR image"), "{error}");
    }
}
