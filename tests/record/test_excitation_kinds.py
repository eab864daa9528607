"""Every excitation kind and direction makes a recording that the format's independent checker accepts,
and the reader still reads the first two format versions."""

import subprocess
import sys
from pathlib import Path

import orjson
import pytest
from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer

from softarm.config import load_config
from softarm.record.reader import read_recording
from softarm.sim.simulate import simulate

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


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


def older(source_path: Path, target_path: Path, version: int) -> None:
    """A copy of a /3 recording as softarm wrote /2 (no disturbances: no key, no channel) or /1 (as /2, its
    excitation without kind and direction)."""
    with open(source_path, "rb") as source, open(target_path, "wb") as target:
        reader, writer = make_reader(source), Writer(target, compression=CompressionType.ZSTD)
        writer.start()
        summary = reader.get_summary()
        schemas = {i: writer.register_schema(s.name, s.encoding, s.data) for i, s in summary.schemas.items()}
        channels = {i: writer.register_channel(c.topic, c.message_encoding, schemas[c.schema_id])
                    for i, c in summary.channels.items() if c.topic != "/arm/disturbance"}
        for meta in reader.iter_metadata():
            values = dict(meta.metadata)
            if meta.name == "softarm":
                model = orjson.loads(values["model"])
                del model["disturbances"]
                if version == 1:
                    model["excitation"] = {k: model["excitation"][k]
                                           for k in ("amplitude", "frequencies", "time_offset")}
                values = {"format": f"softarm-recording/{version}", "model": orjson.dumps(model).decode()}
            writer.add_metadata(meta.name, values)
        for _, channel, message in reader.iter_messages():
            if channel.id in channels:
                writer.add_message(channels[channel.id], message.log_time, message.data, message.publish_time)
        writer.finish()


@pytest.mark.parametrize("version", [1, 2])
def test_recordings_of_the_first_versions_read_as_the_papers_sideways_drive_undisturbed(tmp_path, version):
    simulate(load_config(overrides={"run.duration": 0.3}), tmp_path / "v3.mcap")
    older(tmp_path / "v3.mcap", tmp_path / "old.mcap", version)
    old, new = read_recording(tmp_path / "old.mcap"), read_recording(tmp_path / "v3.mcap")
    assert old.model["excitation"] == new.model["excitation"]
    assert (old.frames == new.frames).all() and (old.stretch == new.stretch).all()
    assert old.active.shape == (30, 0) and "disturbances" not in old.model
