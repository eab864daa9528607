"""MCAP records in file order, chunks opened, read with one struct call per message.

`mcap.stream_reader` reads every field through a file-like stream, message indexes included, which
made it most of the time a corpus took to load (about 2 400 messages a chunk). This reads the same
records from whole record bodies: messages as `mcap.records.Message`, schema, channel, metadata and
chunk records through mcap's own parsers; index, statistics and summary records are skipped unread,
as a reader that does not need them may.
"""

import os
import struct
from io import BytesIO
from typing import BinaryIO, Iterator, Union

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import Channel, Chunk, Message, Metadata, Schema
from mcap.stream_reader import get_chunk_data_stream

RECORD = struct.Struct("<BQ")     # opcode, content length
MAX_CHUNK = 1 << 28               # bytes a chunk may unpack to: softarm writes ~1 MB, a damaged header claims more
MESSAGE = struct.Struct("<HIQQ")  # channel id, sequence, log time, publish time
PARSED = {Opcode.CHANNEL: Channel, Opcode.SCHEMA: Schema, Opcode.METADATA: Metadata, Opcode.CHUNK: Chunk}

Record = Union[Message, Channel, Schema, Metadata]


def file_records(f: BinaryIO, magic: bytes) -> Iterator[Record]:
    """Records after the opening magic up to the footer; raises struct.error (or mcap's errors) where the
    bytes stop making sense, a file cut short before its closing magic included. No record is read past the
    end of the file, so a damaged length costs no memory."""
    size = os.fstat(f.fileno()).st_size
    f.seek(len(magic))
    while True:
        head = f.read(RECORD.size)
        if len(head) < RECORD.size:
            raise struct.error("the file ends before its footer")
        opcode, length = RECORD.unpack(head)
        if length > size - f.tell():
            raise struct.error(f"a record claims {length} bytes, more than the file holds after it")
        if opcode == Opcode.FOOTER:
            if len(f.read(length)) < length or f.read(len(magic)) != magic:
                raise struct.error("the file ends inside its footer or closing magic")
            return
        if opcode != Opcode.MESSAGE and opcode not in PARSED:
            f.seek(length, 1)
            continue
        body = f.read(length)
        if len(body) < length:
            raise struct.error(f"the file ends {length - len(body)} bytes into a record")
        if opcode == Opcode.CHUNK:
            yield from chunk_records(Chunk.read(ReadDataStream(BytesIO(body))))
        else:
            yield from _records(body, opcode, 0, length)


def chunk_records(chunk: Chunk) -> Iterator[Record]:
    """The chunk's records in order, once its CRC is checked."""
    if chunk.uncompressed_size > MAX_CHUNK:
        raise struct.error(f"a chunk claims to unpack to {chunk.uncompressed_size} bytes")
    stream, length = get_chunk_data_stream(chunk, validate_crc=True)  # zstd, lz4 or none, as mcap reads them
    data = stream.read(length)
    offset = 0
    while offset < length:
        opcode, size = RECORD.unpack_from(data, offset)
        start = offset + RECORD.size
        offset = start + size
        if offset > length:
            raise struct.error(f"a chunk record runs {offset - length} bytes past its chunk")
        yield from _records(data, opcode, start, offset)


def _records(data: bytes, opcode: int, start: int, end: int) -> Iterator[Record]:
    """The record in data[start:end], if it is one a reader of softarm files uses (none otherwise)."""
    if opcode == Opcode.MESSAGE:
        channel, sequence, log_time, publish_time = MESSAGE.unpack_from(data, start)
        yield Message(channel_id=channel, sequence=sequence, log_time=log_time, publish_time=publish_time,
                      data=data[start + MESSAGE.size:end])
    elif opcode in PARSED:
        yield PARSED[opcode].read(ReadDataStream(BytesIO(data[start:end])))
