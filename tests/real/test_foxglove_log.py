"""A Foxglove-style log imports as a ROS 2 one does: protobuf `foxglove.CompressedImage` frames stamped by their
`timestamp`, and JSON sensor messages with a Foxglove time `{sec, nsec}`."""

import json

import pytest
from foxglove_schemas_protobuf.CompressedImage_pb2 import CompressedImage
from mcap.reader import make_reader
from mcap.writer import Writer as McapWriter
from mcap_protobuf.schema import build_file_descriptor_set
from mcap_ros2.decoder import DecoderFactory

from softarm.real.convert import import_log
from softarm.real.settings import ImportSettings

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def foxglove_copy(bag, path) -> None:
    """The robot bag's camera as foxglove.CompressedImage (protobuf) and its stretch as JSON, in one MCAP."""
    with open(bag.path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        messages = [(channel.topic, m.log_time, msg) for _, channel, m, msg in
                    reader.iter_decoded_messages(topics=[bag.camera_topic, bag.stretch_topic])]
    with open(path, "wb") as out:
        writer = McapWriter(out)
        writer.start()
        camera = writer.register_channel("/lab/camera", "protobuf", writer.register_schema(
            "foxglove.CompressedImage", "protobuf", build_file_descriptor_set(CompressedImage).SerializeToString()))
        stretch = writer.register_channel("/lab/stretch", "json", writer.register_schema(
            "softarm_lab.Stretch", "jsonschema", b'{"type": "object"}'))
        for topic, log_time, msg in messages:
            stamp = {"sec": msg.header.stamp.sec, "nsec": msg.header.stamp.nanosec}
            if topic == bag.camera_topic:
                image = CompressedImage(format="jpeg", data=bytes(msg.data), frame_id="cam")
                image.timestamp.seconds, image.timestamp.nanos = stamp["sec"], stamp["nsec"]
                channel, data = camera, image.SerializeToString()
            else:
                channel, data = stretch, json.dumps({"timestamp": stamp, "values": list(msg.data)}).encode()
            writer.add_message(channel, log_time=log_time, data=data, publish_time=log_time)
        writer.finish()


def test_a_foxglove_log_with_json_sensors_imports(robot_bag, imported, tmp_path):
    foxglove_copy(robot_bag, tmp_path / "fox.mcap")
    settings = ImportSettings("/lab/camera", "/lab/stretch:values", roi=robot_bag.roi)
    report = import_log(tmp_path / "fox.mcap", tmp_path / "rec.mcap", settings)
    ros = imported[0]
    assert abs(report.lag - robot_bag.offset) < 1 / 30 and report.dropped == len(robot_bag.dropped)
    assert report.frames == ros.frames and abs(report.coverage - ros.coverage) < 1e-3
