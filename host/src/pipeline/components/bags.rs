//! `ToF.McapWriter`: a run's frames as a ROS 2 bag (`fileName` in the sink's folder), written
//! frame by frame and given its name when the run ends (a failed or cancelled run's frames
//! too). Each producer has its topics: `/<producer>/raw_a`, `/<producer>/raw_b` (a frame's
//! four phase images of a channel one below the other, `16UC1` — the layout `RawFrameFile`
//! reads), `/<producer>/distance` (`32FC1` metres, REP 118's depth), `…/amplitude`,
//! `…/intensity`, `…/truth` (the true distances, when the frames know them) and `…/cloud`
//! (`PointCloud2` with normals). A frame is stamped when it was recorded (a bag's frames keep
//! their times), else k / `frameRate` s for frame k.

use std::sync::Arc;

use gudsl_files::Growing;
use gudsl_formats::bag::{At, BagWriter};
use gudsl_runtime::Image;

use super::{cloud::CloudRead, depth_images, depth_planes, Component, Ctx, Inputs, Outputs, Params, PerFrame};
use crate::pipeline::{
    data::Data,
    executor::{Later, Reads},
    OutputDir,
};

pub struct McapWriter {
    instance: String,
    file: String,
    planes: Vec<&'static str>,
    /// Nanoseconds between frames.
    period: f64,
    frame_id: String,
    /// Each frame's messages, until its reads are back.
    pending: PerFrame<BagFrame>,
    /// The bag, from the first frame that gave it anything until the run ends.
    bag: Option<BagWriter<Growing>>,
}

/// A frame's messages to write, each with its topic, and when the frame was recorded, as the
/// first of its items that knows says.
#[derive(Default)]
struct BagFrame {
    messages: Vec<(String, Pending)>,
    recorded: Option<u64>,
}

/// A message of a frame, as it is known before the frame's reads.
enum Pending {
    /// An image read at the end of the frame.
    Image(Later),
    /// Raw channels A and B, read at the end of the frame.
    Raw(Later),
    /// An image already in host memory (the true distances).
    Known(Arc<Image>),
    Cloud(CloudRead),
}

impl McapWriter {
    pub fn new(params: &Params) -> McapWriter {
        McapWriter {
            instance: params.stage.instance.clone(),
            file: params.text("fileName").to_string(),
            planes: ["distance", "amplitude", "intensity"].into_iter().filter(|p| params.flag(p)).collect(),
            period: 1e9 / params.number("frameRate").max(1e-3),
            frame_id: params.text("frameId").to_string(),
            pending: PerFrame::default(),
            bag: None,
        }
    }

    fn bag(&mut self, output: &mut OutputDir) -> Result<&mut BagWriter<Growing>, String> {
        if self.bag.is_none() {
            self.bag = Some(BagWriter::new(output.create(&self.instance, &self.file)?)?);
        }
        Ok(self.bag.as_mut().expect("just made"))
    }
}

impl BagFrame {
    /// The true distances of `producer`'s item, once a frame.
    fn truth(&mut self, producer: &str, truth: Option<&Arc<Image>>) {
        let topic = format!("/{producer}/truth");
        if let Some(truth) = truth.filter(|_| !self.messages.iter().any(|(t, _)| *t == topic)) {
            self.messages.push((topic, Pending::Known(truth.clone())));
        }
    }
}

impl Component for McapWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let this = self.pending.now(ctx.device);
        for item in inputs.port("RawIn") {
            if let Data::Raw(frame) = &item.data {
                this.recorded = this.recorded.or(frame.stamp);
                let read = Pending::Raw(ctx.device.read_later(&frame.raw));
                this.messages.push((format!("/{}/raw_", item.producer), read));
                this.truth(&item.producer, frame.truth.as_ref());
            }
        }
        for (producer, depth) in depth_images(inputs) {
            this.recorded = this.recorded.or(depth.stamp);
            for (what, tensor) in depth_planes(depth, &self.planes) {
                let read = Pending::Image(ctx.device.read_later(tensor));
                this.messages.push((format!("/{producer}/{what}"), read));
            }
            this.truth(producer, depth.truth.as_ref());
        }
        for item in inputs.port("CloudIn") {
            if let Data::Cloud(cloud) = &item.data {
                this.messages.push((format!("/{}/cloud", item.producer), Pending::Cloud(CloudRead::ask(ctx, cloud))));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        let BagFrame { messages, recorded } = self.pending.take(reads);
        if messages.is_empty() {
            return Ok(Vec::new());
        }
        let stamp = recorded.unwrap_or((ctx.frame as f64 * self.period).round() as u64);
        let frame_id = self.frame_id.clone();
        let bag = self.bag(ctx.output)?;
        for (topic, message) in messages {
            let topic = &topic;
            let at = At { topic, stamp, frame_id: &frame_id };
            match message {
                Pending::Image(later) => {
                    let image = reads.get(later);
                    bag.floats(&at, (image.width, image.height), &image.data)?;
                }
                Pending::Known(image) => bag.floats(&at, (image.width, image.height), &image.data)?,
                Pending::Raw(later) => {
                    let raw = reads.get(later);
                    for (channel, first) in [("a", 0), ("b", 1)] {
                        let planes = super::channel(raw, first);
                        let topic = format!("{topic}{channel}");
                        bag.values(&At { topic: &topic, ..at }, (raw.width, 4 * raw.height), &planes)?;
                    }
                }
                Pending::Cloud(cloud) => {
                    let (points, normals) = cloud.take(reads);
                    bag.cloud(&at, &points, &normals)?
                }
            }
        }
        Ok(Vec::new())
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        match self.bag.take() {
            Some(bag) => output.commit(bag.finish()?).map(|_| ()),
            None => Ok(()),
        }
    }
}
