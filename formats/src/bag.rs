//! ROS 2 bags in MCAP, rosbag2's default store since Iron, through the `mcap` crate. A topic
//! is named after its file: `recording.mcap:/camera/depth`. Its images (`sensor_msgs/msg/Image`
//! in CDR) are checked from the file's summary and first message of the topic — what a check
//! reads —, then read a message at a time on a thread of their own (chunks compressed by zstd
//! or lz4 too), one frame ahead of the run. A run's images and point clouds are written on
//! topics of their own into a file Foxglove, Rerun and the Python `mcap` reader open by the
//! standard schemas.

use std::{
    collections::BTreeMap,
    io::{BufReader, Read, Seek, Write},
    path::{Path, PathBuf},
    sync::Arc,
};

use gudsl_files::Folder;
use mcap::{
    records::MessageHeader,
    sans_io::{LinearReaderOptions, SummaryReadEvent, SummaryReader, SummaryReaderOptions},
    Summary, WriteOptions, Writer,
};
use serde::de::DeserializeOwned;

use crate::{
    arrays::ArrayError,
    frame_stream::FrameStream,
    ros2::{self, Header, Image, MessageError, PointCloud2, Time},
};

/// The longest bag read (1 TiB).
const MAX_BAG_BYTES: u64 = 1 << 40;

/// The longest record (a message, a chunk decompressed) read: 1 GiB.
const MAX_RECORD_BYTES: usize = 1 << 30;

/// Why a bag cannot be read: the file and what is wrong, said of it.
pub type BagError = String;

/// A topic of a bag: the file and the topic's name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Place {
    pub file: PathBuf,
    pub topic: String,
}

impl Place {
    /// The topic a path names, `recording.mcap:/topic`; `None` when the path is no bag's.
    pub fn parse(path: &Path) -> Option<Place> {
        let text = path.to_str()?;
        let (file, topic) = text.rsplit_once(".mcap:")?;
        Some(Place { file: PathBuf::from(format!("{file}.mcap")), topic: topic.to_string() })
    }

    fn shown(&self) -> String {
        format!("{}:{}", self.file.display(), self.topic)
    }
}

/// Whether `path` names a bag (`.mcap`) or a topic of one.
pub fn is_bag(path: &Path) -> bool {
    Place::parse(path).is_some() || path.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
}

/// A topic of images: how many, their size and encoding (from its first message).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImageTopic {
    pub messages: usize,
    pub width: usize,
    pub height: usize,
    pub encoding: String,
    /// Whether its pixels are integers (a depth image of them is in some unit, not metres).
    pub integer: bool,
}

/// Checks the images of the topic `place` names: the file's summary and the topic's first
/// message.
pub fn image_topic(folder: &Folder, place: &Place) -> Result<ImageTopic, BagError> {
    let shown = place.shown();
    let messages = messages_of(folder, place, ros2::IMAGE_SCHEMA.0)?;
    let mut first = None;
    read_messages(folder, place, &mut |image: Image, _| {
        first = Some(image);
        false
    })?;
    let first = first.ok_or_else(|| format!("{shown} holds no message"))?;
    first.values().map_err(|e| format!("{shown}: its first image {e}"))?;
    Ok(ImageTopic {
        messages,
        width: first.width as usize,
        height: first.height as usize,
        integer: first.is_integer().map_err(|e| format!("{shown}: its first image {e}"))?,
        encoding: first.encoding,
    })
}

/// Checks the point clouds of the topic `place` names (the summary and the first message):
/// how many there are.
pub fn cloud_topic(folder: &Folder, place: &Place) -> Result<usize, BagError> {
    let messages = messages_of(folder, place, ros2::POINT_CLOUD_SCHEMA.0)?;
    let mut first = None;
    read_messages(folder, place, &mut |cloud: PointCloud2, _| {
        first = Some(cloud.points());
        false
    })?;
    match first {
        Some(Ok(_)) => Ok(messages),
        Some(Err(e)) => Err(format!("{}: its first cloud {e}", place.shown())),
        None => Err(format!("{} holds no message", place.shown())),
    }
}

/// The clouds of the topic, the first `frames` of them, read a message at a time: each as its
/// points' `x y z nx ny nz`, one point after the other (a cloud that cannot be read is an
/// error at its index).
pub fn clouds(folder: Arc<Folder>, place: &Place, frames: usize) -> FrameStream {
    stream(folder, place, frames, |cloud: PointCloud2, index| {
        let (points, normals) = cloud.points().map_err(|e| format!("its cloud {index} {e}"))?;
        Ok(points.iter().zip(&normals).flat_map(|(p, n)| p.iter().chain(n).copied()).collect())
    })
}

/// How many messages the topic holds, checked to carry `schema` in CDR.
fn messages_of(folder: &Folder, place: &Place, schema: &str) -> Result<usize, BagError> {
    let summary = summary(folder, &place.file)?;
    let channel = channel_of(&summary, place)?;
    let carried = channel.schema.as_ref().map_or("", |s| s.name.as_str());
    if carried != schema || channel.message_encoding != "cdr" {
        return Err(format!(
            "{} carries {carried} in {}; expected {schema} in cdr",
            place.shown(),
            channel.message_encoding
        ));
    }
    let messages = summary.stats.as_ref().and_then(|s| s.channel_message_counts.get(&channel.id)).copied();
    let messages = messages.ok_or_else(|| format!("{}: its summary counts no messages per topic", place.shown()))?;
    Ok(messages as usize)
}

/// The values of the first `frames` images of the topic, a frame at a time, each of
/// `width`×`height` pixels (a message of another size is an error at its index).
pub fn images(folder: Arc<Folder>, place: &Place, frames: usize, size: (usize, usize)) -> FrameStream {
    stream(folder, place, frames, move |image: Image, index| {
        match (image.width as usize, image.height as usize) == size {
            true => image.values().map_err(|e| format!("its image {index} {e}")),
            false => Err(format!(
                "its image {index} is {}×{}, not {}×{} as the first",
                image.width, image.height, size.0, size.1
            )),
        }
    })
}

/// The first `frames` messages of the topic as `values` makes them of each (with its index),
/// with their log times, read on the stream's thread; the first that cannot be made stops it.
fn stream<T, V>(folder: Arc<Folder>, place: &Place, frames: usize, values: V) -> FrameStream
where
    T: DeserializeOwned,
    V: Fn(T, usize) -> Result<Vec<f32>, String> + Send + 'static,
{
    let place = place.clone();
    let shown = PathBuf::from(place.shown());
    FrameStream::spawn(&shown.clone(), move |send| {
        let (mut index, mut failed) = (0, None);
        let mut each = |message: T, stamp: u64| {
            let made = values(message, index);
            index += 1;
            match made {
                Ok(made) => send(made, Some(stamp)) && index < frames,
                Err(message) => {
                    failed = Some(message);
                    false
                }
            }
        };
        let read = read_messages(&folder, &place, &mut each);
        match failed.map(Err).unwrap_or(read) {
            Ok(()) => Ok(()),
            Err(message) => Err(ArrayError::invalid(&shown, message.replace(&format!("{}: ", shown.display()), ""))),
        }
    })
}

/// Hands each message of the topic, with its log time, to `each` in the file's order while it
/// says to go on.
fn read_messages<T: DeserializeOwned>(
    folder: &Folder,
    place: &Place,
    each: &mut dyn FnMut(T, u64) -> bool,
) -> Result<(), BagError> {
    let opened = folder.open_file(&place.file, MAX_BAG_BYTES).map_err(|e| e.to_string())?;
    messages_in(BufReader::new(opened.file), place, each)
}

/// Hands each message of the topic in `source` (a bag) to `each` while it says to go on.
fn messages_in<T: DeserializeOwned>(
    source: impl Read,
    place: &Place,
    each: &mut dyn FnMut(T, u64) -> bool,
) -> Result<(), BagError> {
    let shown = place.shown();
    let options = LinearReaderOptions::default().with_record_length_limit(MAX_RECORD_BYTES);
    for message in mcap::io::MessageReader::new_with_options(source, options) {
        let message = message.map_err(|e| format!("{}: {e}", place.file.display()))?;
        if message.channel.topic != place.topic {
            continue;
        }
        let decoded: T = ros2::decode(&message.data).map_err(|e| format!("{shown}: message {e}"))?;
        if !each(decoded, message.log_time) {
            break;
        }
    }
    Ok(())
}

/// The bag's summary (its topics and their message counts), read from the end of the file.
fn summary(folder: &Folder, file: &Path) -> Result<Summary, BagError> {
    let opened = folder.open_file(file, MAX_BAG_BYTES).map_err(|e| e.to_string())?;
    summary_of(opened.file, opened.len, file)
}

/// The summary of the bag `source` (`len` bytes) holds.
fn summary_of(mut source: impl Read + Seek, len: u64, file: &Path) -> Result<Summary, BagError> {
    let unreadable = |e: &dyn std::fmt::Display| format!("{}: is not a readable MCAP file ({e})", file.display());
    let options = SummaryReaderOptions::default().with_file_size(len).with_record_length_limit(MAX_RECORD_BYTES);
    let mut reader = SummaryReader::new_with_options(options);
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| unreadable(&e))? {
            SummaryReadEvent::ReadRequest(need) => {
                let read = source.read(reader.insert(need)).map_err(|e| unreadable(&e))?;
                reader.notify_read(read);
            }
            SummaryReadEvent::SeekRequest(to) => reader.notify_seeked(source.seek(to).map_err(|e| unreadable(&e))?),
        }
    }
    reader.finish().ok_or_else(|| {
        format!("{}: has no summary: the recording was not closed (`mcap recover` mends it)", file.display())
    })
}

/// What every topic of images or clouds in the bag `bytes` holds, as values: what the fuzz
/// target feeds (the summary, the messages, their CDR, their pixels and points all read).
pub fn contents_in_bytes(bytes: &[u8]) -> Result<Vec<Vec<f32>>, BagError> {
    let file = Path::new("fuzz.mcap");
    let summary = summary_of(std::io::Cursor::new(bytes), bytes.len() as u64, file)?;
    let mut values = Vec::new();
    for channel in summary.channels.values() {
        let place = Place { file: file.to_path_buf(), topic: channel.topic.clone() };
        let mut failed = None;
        let mut keep = |read: Result<Vec<f32>, MessageError>| match read {
            Ok(read) => values.push(read),
            Err(e) => failed = Some(e),
        };
        match channel.schema.as_ref().map(|s| s.name.as_str()) {
            Some(name) if name == ros2::POINT_CLOUD_SCHEMA.0 => {
                messages_in(bytes, &place, &mut |c: PointCloud2, _| {
                    keep(c.points().map(|(p, _)| p.concat()));
                    true
                })?
            }
            _ => messages_in(bytes, &place, &mut |image: Image, _| {
                keep(image.values());
                true
            })?,
        }
        if let Some(e) = failed {
            return Err(e);
        }
    }
    Ok(values)
}

/// The channel of the topic, or an error listing the topics there are.
fn channel_of<'s>(summary: &'s Summary, place: &Place) -> Result<&'s mcap::Channel<'static>, BagError> {
    let mut channels: Vec<_> = summary.channels.values().collect();
    channels.sort_by_key(|c| c.id);
    if let Some(channel) = channels.iter().find(|c| c.topic == place.topic) {
        return Ok(channel);
    }
    let topics: Vec<String> = channels
        .iter()
        .map(|c| format!("{} ({})", c.topic, c.schema.as_ref().map_or("no schema", |s| s.name.as_str())))
        .collect();
    Err(format!(
        "{} has no topic `{}`; its topics: {}",
        place.file.display(),
        place.topic,
        if topics.is_empty() { "none".to_string() } else { topics.join(", ") }
    ))
}

/// A bag being written: images and point clouds, each topic a channel of its own, in
/// zstd-compressed chunks, stamped by the caller.
pub struct BagWriter<W: Write + Seek> {
    writer: Writer<W>,
    channels: BTreeMap<String, u16>,
    sequence: u32,
}

impl<W: Write + Seek> BagWriter<W> {
    pub fn new(sink: W) -> Result<BagWriter<W>, BagError> {
        let options = WriteOptions::new().profile("ros2").library("gudsl");
        let writer = options.create(sink).map_err(|e| format!("cannot start an MCAP file ({e})"))?;
        Ok(BagWriter { writer, channels: BTreeMap::new(), sequence: 0 })
    }

    /// A one-channel image of 32-bit floats (`32FC1`).
    pub fn floats(&mut self, at: &At, size: (usize, usize), values: &[f32]) -> Result<(), BagError> {
        let image = Image::floats(at.header(), size.0, size.1, values);
        self.message(at, ros2::IMAGE_SCHEMA, &ros2::encode(&image))
    }

    /// A one-channel image: `16UC1` when every value is a whole number in 0..=65535 (raw
    /// channels), else `32FC1`.
    pub fn values(&mut self, at: &At, size: (usize, usize), values: &[f32]) -> Result<(), BagError> {
        match Image::sixteen_bits(at.header(), size.0, size.1, values) {
            Some(image) => self.message(at, ros2::IMAGE_SCHEMA, &ros2::encode(&image)),
            None => self.floats(at, size, values),
        }
    }

    /// A point cloud with normals (`PointCloud2`).
    pub fn cloud(&mut self, at: &At, points: &[[f32; 3]], normals: &[[f32; 3]]) -> Result<(), BagError> {
        let cloud = PointCloud2::with_normals(at.header(), points, normals);
        self.message(at, ros2::POINT_CLOUD_SCHEMA, &ros2::encode(&cloud))
    }

    fn message(&mut self, at: &At, schema: (&str, &str), data: &[u8]) -> Result<(), BagError> {
        let (topic, stamp) = (at.topic, at.stamp);
        let failed = |e: mcap::McapError| format!("cannot write {topic} ({e})");
        let channel_id = match self.channels.get(topic) {
            Some(&id) => id,
            None => {
                let schema_id = self.writer.add_schema(schema.0, "ros2msg", schema.1.as_bytes()).map_err(failed)?;
                let id = self.writer.add_channel(schema_id, topic, "cdr", &BTreeMap::new()).map_err(failed)?;
                *self.channels.entry(topic.to_string()).or_insert(id)
            }
        };
        self.sequence += 1;
        let header = MessageHeader { channel_id, sequence: self.sequence, log_time: stamp, publish_time: stamp };
        self.writer.write_to_known_channel(&header, data).map_err(failed)
    }

    /// Writes the summary (topics, counts, the chunk index) and gives the sink back.
    pub fn finish(mut self) -> Result<W, BagError> {
        self.writer.finish().map_err(|e| format!("cannot finish the MCAP file ({e})"))?;
        Ok(self.writer.into_inner())
    }
}

/// Where a message goes: its topic, its time stamp (ns) and its coordinate frame.
#[derive(Debug, Clone, Copy)]
pub struct At<'a> {
    pub topic: &'a str,
    pub stamp: u64,
    pub frame_id: &'a str,
}

impl At<'_> {
    fn header(&self) -> Header {
        Header { stamp: Time::from_nanos(self.stamp), frame_id: self.frame_id.to_string() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(frames: usize) -> (tempfile::TempDir, Folder) {
        let dir = tempfile::tempdir().unwrap();
        let mut bag = BagWriter::new(std::io::Cursor::new(Vec::new())).unwrap();
        for k in 0..frames {
            let values: Vec<f32> = (0..6).map(|v| (v + 10 * k) as f32).collect();
            let at = |topic| At { topic, stamp: k as u64 * 1000, frame_id: "tof" };
            bag.floats(&at("/tof/depth"), (3, 2), &values).unwrap();
            bag.cloud(&at("/tof/cloud"), &[[1.0, 2.0, 3.0]], &[[0.0, 0.0, 1.0]]).unwrap();
        }
        std::fs::write(dir.path().join("run.mcap"), bag.finish().unwrap().into_inner()).unwrap();
        let folder = Folder::open(dir.path()).unwrap();
        (dir, folder)
    }

    #[test]
    fn a_written_topic_reads_back_frame_by_frame() {
        let (dir, folder) = written(3);
        let place = Place::parse(&dir.path().join("run.mcap:/tof/depth")).unwrap();
        let topic = image_topic(&folder, &place).unwrap();
        assert_eq!(topic, ImageTopic { messages: 3, width: 3, height: 2, encoding: "32FC1".into(), integer: false });
        let stream = images(Arc::new(folder), &place, 2, (3, 2));
        assert_eq!(stream.next_frame().unwrap(), vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(stream.next_stamped().unwrap(), (vec![10.0, 11.0, 12.0, 13.0, 14.0, 15.0], Some(1000)));
        assert!(stream.next_frame().is_err(), "two frames were asked for");
    }

    #[test]
    fn a_wrong_topic_or_schema_or_file_is_told_with_what_there_is() {
        let (dir, folder) = written(1);
        let place = |topic: &str| Place::parse(&dir.path().join(format!("run.mcap:{topic}"))).unwrap();
        let error = image_topic(&folder, &place("/tof/dpeth")).unwrap_err();
        assert!(
            error.contains("has no topic `/tof/dpeth`; its topics: /tof/depth (sensor_msgs/msg/Image), /tof/cloud"),
            "{error}"
        );
        let error = image_topic(&folder, &place("/tof/cloud")).unwrap_err();
        assert!(
            error.contains("carries sensor_msgs/msg/PointCloud2 in cdr; expected sensor_msgs/msg/Image"),
            "{error}"
        );
        std::fs::write(dir.path().join("bad.mcap"), b"\x89MCAP0\r\nnot really").unwrap();
        let bad = Place::parse(&dir.path().join("bad.mcap:/x")).unwrap();
        assert!(image_topic(&folder, &bad).unwrap_err().contains("is not a readable MCAP file"));
        assert!(Place::parse(Path::new("depth.npy")).is_none());
        assert!(is_bag(Path::new("a/b.MCAP")) && is_bag(Path::new("a/b.mcap:/t")));
    }

    #[test]
    fn an_image_of_another_size_stops_the_stream_at_its_index() {
        let dir = tempfile::tempdir().unwrap();
        let mut bag = BagWriter::new(std::io::Cursor::new(Vec::new())).unwrap();
        bag.floats(&At { topic: "/d", stamp: 0, frame_id: "" }, (2, 2), &[1.0; 4]).unwrap();
        bag.floats(&At { topic: "/d", stamp: 1, frame_id: "" }, (3, 1), &[1.0; 3]).unwrap();
        std::fs::write(dir.path().join("b.mcap"), bag.finish().unwrap().into_inner()).unwrap();
        let place = Place::parse(&dir.path().join("b.mcap:/d")).unwrap();
        let stream = images(Arc::new(Folder::open(dir.path()).unwrap()), &place, 5, (2, 2));
        assert!(stream.next_frame().is_ok());
        let error = stream.next_frame().unwrap_err().to_string();
        assert!(error.contains("b.mcap:/d: its image 1 is 3×1, not 2×2 as the first"), "{error}");
    }
}
