"""Every excitation kind and direction makes a recording that the format's independent checker accepts,
and the reader still reads the first format version."""

import subprocess
import sys
from pathlib import Path

import orjson
import pytest
from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer

from softarm.config import load_config
from softarm.record.reader import read_recording
from softarm.sim.run import simulate

CHECKER = Path(__file__).resolve().parents[3] / "shared" / "tools" / "check_recording.py"  # beside the clone
KINDS = {
    "product_of_sines": {},
    "sum_of_sines band": {"excitation.kind": "sum_of_sines", "excitation.sum_of_sines.band": [0.3, 2.5],
                          "excitation.sum_of_sines.rms": 0.003},
    "sum_of_sines listed": {"excitation.kind": "sum_of_sines", "excitation.sum_of_sines.amplitudes": [0.004],
                            "excitation.sum_of_sines.frequencies": [0.7], "excitation.sum_of_sines.phases": [1.0]},
}


@pytest.mark.parametrize("direction", [[1.0, 0.0], [0.0, 1.0], [0.6, -0.8]], ids=["sideways", "up", "slanted"])
@pytest.mark.parametrize("kind", list(KINDS))
def test_every_kind_and_direction_records_a_file_the_independent_checker_accepts(tmp_path, kind, direction):
    config = load_config(overrides={"run.duration": 1.0, "run.seed": 2, "excitation.direction": direction,
                                    **KINDS[kind]})
    simulate(config, tmp_path / "r.mcap")
    rec = read_recording(tmp_path / "r.mcap")
    assert rec.model["excitation"]["kind"] == config.excitation.kind
    assert rec.model["excitation"]["direction"] == direction
    if not CHECKER.exists():
        pytest.skip(f"the shared format checker is not beside this clone ({CHECKER})")
    done = subprocess.run([sys.executable, str(CHECKER), str(tmp_path / "r.mcap")], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_version_1_recording_reads_as_the_papers_sideways_drive(tmp_path):
    simulate(load_config(overrides={"run.duration": 0.3}), tmp_path / "v2.mcap")
    with open(tmp_path / "v2.mcap", "rb") as source, open(tmp_path / "v1.mcap", "wb") as target:
        reader, writer = make_reader(source), Writer(target, compression=CompressionType.ZSTD)
        writer.start()
        summary = reader.get_summary()
        schemas = {i: writer.register_schema(s.name, s.encoding, s.data) for i, s in summary.schemas.items()}
        channels = {i: writer.register_channel(c.topic, c.message_encoding, schemas[c.schema_id])
                    for i, c in summary.channels.items()}
        for meta in reader.iter_metadata():
            values = dict(meta.metadata)
            if meta.name == "softarm":
                model = orjson.loads(values["model"])
                model["excitation"] = {k: model["excitation"][k] for k in ("amplitude", "frequencies", "time_offset")}
                values = {"format": "softarm-recording/1", "model": orjson.dumps(model).decode()}
            writer.add_metadata(meta.name, values)
        for _, channel, message in reader.iter_messages():
            writer.add_message(channels[channel.id], message.log_time, message.data, message.publish_time)
        writer.finish()
    old, new = read_recording(tmp_path / "v1.mcap"), read_recording(tmp_path / "v2.mcap")
    assert old.model["excitation"] == new.model["excitation"]
    assert (old.frames == new.frames).all() and (old.stretch == new.stretch).all()
