"""The fast record scan reads exactly the records the mcap library's own stream reader reads."""

from mcap.records import Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader

from softarm.record.scan import file_records

MAGIC = b"\x89MCAP0\r\n"


def test_scan_equals_the_mcap_stream_reader(recordings):
    path = recordings / "s0.mcap"
    with open(path, "rb") as f:
        ours = list(file_records(f, MAGIC))
    with open(path, "rb") as f:
        theirs = [r for r in StreamReader(f, validate_crcs=True).records
                  if isinstance(r, (Message, Channel, Schema, Metadata))]
    assert ours == theirs and sum(isinstance(r, Message) for r in ours) > 1000
