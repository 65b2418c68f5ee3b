"""Reads a ROS 2 bag (MCAP) as a Python user would, with the `mcap` package and its ROS 2
decoder (`mcap-ros2-support`), and prints what it holds as JSON: per topic its schema, message
encoding, message count, and each message's decoded fields (images: size, encoding, stamp and
their pixel values; point clouds: fields, point step and points).

    python3 tests/mcap/read_bag.py BAG
"""

import json
import struct
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

FORMATS = {"32FC1": "f", "16UC1": "H", "mono16": "H", "8UC1": "B", "mono8": "B"}


def image(msg):
    fmt = FORMATS[msg.encoding]
    endian = ">" if msg.is_bigendian else "<"
    row = struct.calcsize(fmt) * msg.width
    values = []
    for y in range(msg.height):
        line = bytes(msg.data[y * msg.step : y * msg.step + row])
        values.extend(struct.unpack(f"{endian}{msg.width}{fmt}", line))
    return {"width": msg.width, "height": msg.height, "encoding": msg.encoding, "values": values}


def cloud(msg):
    data = bytes(msg.data)
    points = [struct.unpack_from("<6f", data, k * msg.point_step) for k in range(msg.width * msg.height)]
    fields = [[f.name, f.offset, f.datatype, f.count] for f in msg.fields]
    return {"fields": fields, "point_step": msg.point_step, "points": points}


def main(path):
    topics = {}
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        for channel in summary.channels.values():
            topics[channel.topic] = {
                "schema": summary.schemas[channel.schema_id].name,
                "encoding": channel.message_encoding,
                "count": summary.statistics.channel_message_counts[channel.id],
                "messages": [],
            }
        for schema, channel, message, msg in reader.iter_decoded_messages():
            decoded = cloud(msg) if schema.name == "sensor_msgs/msg/PointCloud2" else image(msg)
            decoded["log_time"] = message.log_time
            decoded["stamp"] = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
            decoded["frame_id"] = msg.header.frame_id
            topics[channel.topic]["messages"].append(decoded)
    json.dump(topics, sys.stdout)


if __name__ == "__main__":
    main(sys.argv[1])
