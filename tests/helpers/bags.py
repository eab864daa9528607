"""A ROS 2 MCAP log rewritten as the bags labs keep, by rosbags' own writers and read back with the `mcap` package, so
that nothing of softarm's reading is used to make what softarm must read: a ROS 2 bag folder (sqlite3 storage,
message definitions stored) and a ROS 1 `.bag` (each message converted from CDR to ROS 1's serialisation)."""

from pathlib import Path

from mcap.reader import make_reader
from rosbags.convert.converter import migrate_bytes
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore


def _messages(mcap: Path) -> tuple[list[tuple[str, str, str]], list[tuple[str, int, bytes]]]:
    """The log's (topic, message type, definition) per channel and its (topic, log time, CDR bytes) in order."""
    with open(mcap, "rb") as f:
        reader = make_reader(f)
        channels = {(c.topic, s.name, s.data.decode()) for s, c, _ in reader.iter_messages()}
        f.seek(0)
        messages = [(c.topic, m.log_time, m.data) for _, c, m in make_reader(f).iter_messages(log_time_order=True)]
    return sorted(channels), messages


def _typestore(channels: list[tuple[str, str, str]]):
    store = get_typestore(Stores.LATEST)
    for _, msgtype, definition in channels:
        if msgtype not in store.fielddefs:
            store.register(get_types_from_msg(definition, msgtype))
    return store


def ros2_bag(mcap: Path, folder: Path) -> Path:
    """`folder` written as a ROS 2 bag in sqlite3 storage (format version 9)."""
    channels, messages = _messages(mcap)
    store = _typestore(channels)
    with Ros2Writer(folder, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        connections = {topic: writer.add_connection(topic, msgtype, typestore=store) for topic, msgtype, _ in channels}
        for topic, log_time, data in messages:
            writer.write(connections[topic], log_time, data)
    return folder


def ros1_bag(mcap: Path, path: Path) -> Path:
    """`path` written as a ROS 1 bag: every message migrated to its ROS 1 type (Noetic's, a header with `seq`), as
    rosbags' converter does, and serialised as ROS 1 does."""
    channels, messages = _messages(mcap)
    source = _typestore(channels)
    target = get_typestore(Stores.ROS1_NOETIC)
    for _, msgtype, definition in channels:
        if msgtype not in target.fielddefs:  # softarm's own: the same fields, ROS 1's header
            target.register(get_types_from_msg(definition.split("\n" + "=" * 80)[0].replace("std_msgs/Header",
                                                                                          "Header"), msgtype))
    types, cache = {topic: msgtype for topic, msgtype, _ in channels}, {}
    with Ros1Writer(path) as writer:
        connections = {topic: writer.add_connection(topic, msgtype, typestore=target) for topic, msgtype, _ in channels}
        for topic, log_time, data in messages:
            writer.write(connections[topic], log_time, migrate_bytes(source, target, types[topic], types[topic], cache,
                                                                    data, src_is2=True, dst_is2=False))
    return path
