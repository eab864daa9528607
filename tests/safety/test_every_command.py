"""Every command of the command line through the same hostile set, as a hostile but realistic user would run it:
an output onto an input, onto the `.part` and the lock an output brings with it, numbers out of range, Ctrl-C,
two Ctrl-C close together, SIGTERM. Every case answers in one line and a non-zero exit, leaves every input's
bytes as they were and leaves no partial output or lock behind; an interrupted command exits 130 and says what
it kept. A command added to `softarm --help` fails `test_the_harness_covers_every_command` until it has its row.
"""

import hashlib
import shutil
import signal
import subprocess
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

import pytest
import typer
from softarm_cli.main import app

from tests.helpers.cli import SOFTARM, assert_one_line_error, softarm
from tests.helpers.suites import mini_suite
from tests.helpers.tiny import tiny_toml


@dataclass(frozen=True)
class Row:
    """How one command runs in a folder that holds the shared inputs (x.mcap, m.pt, lab.mcap, suite/, tiny.toml,
    study.toml), what it writes and what it reads."""
    args: list[str]                 # a short run, writing OUT where it writes a file the user names
    inputs: list[str]               # the files of the folder it reads
    out: Optional[str] = None       # the file output named by the user, if it has one
    bad: list[list[str]] = field(default_factory=list)  # extra arguments out of range, each refused
    long: Optional[list[str]] = None  # a run long enough to be interrupted (None: nothing long to interrupt)
    why: str = ""                   # why a kind of case does not apply


ROWS: dict[str, Row] = {
    "config": Row(["config"], [], why="prints the defaults: no file, no number, nothing long"),
    "sim": Row(["sim", "--config", "tiny.toml", "--duration", "1", "--out", "OUT"], ["tiny.toml"], "o.mcap",
               [["--duration", "-1"], ["--duration", "nan"], ["--arms", "0"], ["--seed", "-1"], ["--substeps", "0"]],
               ["sim", "--duration", "3000", "--out", "sim_long.mcap"]),
    "train": Row(["train", "x.mcap", "--config", "tiny.toml", "--out", "OUT"], ["x.mcap", "tiny.toml"], "o.pt",
                 [["--minutes", "nan"], ["--latent", "0"], ["--seed", "-1"], ["--epochs-ae", "0"]],
                 ["train", "long.mcap", "--config", "tiny.toml", "--out", "long.pt"]),
    "adapt": Row(["adapt", "m.pt", "x.mcap", "--seconds", "1", "--from", "1", "--out", "OUT"], ["m.pt", "x.mcap"],
                 "o.pt", [["--seconds", "nan"], ["--seconds", "-1"], ["--from", "1e9"]],
                 ["adapt", "m.pt", "long.mcap", "--seconds", "20", "--from", "5", "--out", "long.pt"]),
    "replay": Row(["replay", "m.pt", "x.mcap", "--mcap", "OUT"], ["m.pt", "x.mcap"], "o.mcap",
                  [["--blind", "nan:1"], ["--png-span", "3:1"]],
                  ["replay", "m.pt", "long.mcap", "--rrd", "long.rrd"]),
    "evaluate": Row(["evaluate", "m.pt", "suite", "--json", "OUT"], ["m.pt", "suite/suite.json", "suite/a.mcap"],
                    "o.json", [["--sensor-noise", "noise=nan"], ["--sensor-noise", "noise=-1"]],
                    ["evaluate", "m.pt", "longsuite", "--json", "long.json"]),
    "corpus": Row(["corpus", "c", "--arms", "1", "--duration", "1", "--preset", "paper"], [],
                  bad=[["--arms", "0"], ["--duration", "nan"], ["--duration", "-2"]],
                  long=["corpus", "longcorpus", "--arms", "19", "--duration", "200"],
                  why="writes a folder the user names, no file"),
    "suite": Row(["suite", "s"], [], long=["suite", "longsuite2"],
                 why="writes a folder the user names, no file; takes no number"),
    "demo": Row(["demo", "--folder", "d"], [], long=["demo", "--folder", "longdemo"],
                why="writes a folder the user names, no file; takes no number"),
    "study": Row(["study", "study.toml", "--out", "st"], ["study.toml"], bad=[["--trials", "0"]],
                 long=["study", "sensors", "--quick", "--out", "longstudy"],
                 why="writes a folder the user names, no file"),
    "babble": Row(["babble", "b", "--episodes", "1", "--seconds", "1", "--config", "tiny.toml"], ["tiny.toml"],
                  bad=[["--episodes", "0"], ["--episodes", "-3"], ["--episodes", "1000000000000"],
                       ["--seconds", "1e12"], ["--seconds", "nan"], ["--seed", "-1"]],
                  long=["babble", "longbabble", "--episodes", "50", "--seconds", "20"],
                  why="writes a folder of episodes, never an existing one"),
    "import": Row(["import", "lab.mcap", "--camera", "/camera/image_raw/compressed", "--sensors", "/arm/stretch:data",
                   "--background", "bg.png", "--out", "OUT"], ["lab.mcap", "bg.png"], "o.mcap",
                  [["--frame-dt", "1e-9"], ["--frame-dt", "nan"], ["--lag", "nan"], ["--max-lag", "-1"]],
                  ["import", "midlab_bag.mcap", "--camera", "/camera/image_raw/compressed", "--sensors",
                   "/arm/stretch:data", "--out", "midlab.mcap"]),
    "robot-log": Row(["robot-log", "x.mcap", "--out", "OUT"], ["x.mcap"], "o.mcap",
                     [["--offset", "nan"], ["--offset", "1e9"]], ["robot-log", "mid.mcap", "--out", "midlab2.mcap"]),
}


def test_the_harness_covers_every_command():
    group = typer.main.get_command(app)
    listed = group.list_commands(group.context_class(group, info_name="softarm"))
    assert sorted(listed) == sorted(ROWS), "every command of `softarm --help` needs its row in ROWS"


@pytest.fixture(scope="module")
def shared(recordings, tiny_checkpoint, tmp_path_factory) -> Path:
    """The inputs every row reads, made once: recordings, a checkpoint, robots' bags of them, suites, configs, a
    background image."""
    from PIL import Image

    from softarm.config import load_config
    from softarm.real.robot_log import make_robot_log
    from softarm.sim.simulate import simulate

    folder = tmp_path_factory.mktemp("shared")
    shutil.copy(recordings / "s1.mcap", folder / "x.mcap")
    shutil.copy(tiny_checkpoint.checkpoint, folder / "m.pt")
    (folder / "tiny.toml").write_text(tiny_toml())
    (folder / "study.toml").write_text('name = "tiny"\nvariable = "latent"\n[[trials]]\nname = "l4"\nvalue = 4\n'
                                       '[trials.overrides]\n"train.latent" = 4\n')
    Image.new("RGB", (640, 480), (90, 120, 160)).save(folder / "bg.png")
    simulate(load_config(overrides={"run.duration": 60.0, "run.seed": 2}), folder / "long.mcap")
    simulate(load_config(overrides={"run.duration": 30.0, "run.seed": 3}), folder / "mid.mcap")
    make_robot_log(folder / "x.mcap", folder / "lab.mcap")
    make_robot_log(folder / "mid.mcap", folder / "midlab_bag.mcap")
    mini_suite(folder / "suite", folder / "x.mcap")
    mini_suite(folder / "longsuite", folder / "long.mcap")
    return folder


def room_of(shared: Path, folder: Path) -> Path:
    """A folder holding a copy of every shared input."""
    folder.mkdir(exist_ok=True)
    for item in shared.iterdir():
        (shutil.copytree if item.is_dir() else shutil.copy)(item, folder / item.name)
    return folder


@pytest.fixture
def room(shared, tmp_path) -> Path:
    return room_of(shared, tmp_path / "room")


def digests(folder: Path, names: list[str]) -> dict[str, str]:
    return {n: hashlib.sha256((folder / n).read_bytes()).hexdigest() for n in names}


def left_behind(folder: Path) -> list[str]:
    """Partial files and locks anywhere under the folder."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.name.endswith(".part")
                  or (p.name.startswith(".") and p.name.endswith(".lock")))


def with_out(row: Row, out: str, replace: Optional[tuple[str, str]] = None) -> list[str]:
    """The row's short run writing `out`, one of its input arguments replaced (old, new) where asked."""
    args = [out if a == "OUT" else a for a in row.args]
    return [replace[1] if replace and a == replace[0] else a for a in args]


FILE_ROWS = [name for name, row in ROWS.items() if row.out and row.inputs]


@pytest.mark.slow
@pytest.mark.parametrize("name", FILE_ROWS)
def test_an_output_onto_an_input_its_part_or_its_lock_is_refused_and_the_input_kept(name, room):
    """The output written onto each input; and each input given under the name of the output's `.part` or lock
    (`y.mcap.part` or `.y.mcap.lock` read, `y.mcap` written): every time refused, with --force too."""
    row = ROWS[name]
    before = digests(room, row.inputs)
    for source in row.inputs:
        assert_one_line_error(softarm(*with_out(row, source), "--force", cwd=room, timeout=120), "is the input")
        if source not in row.args:  # a suite's own files: not named on the command line
            continue
        suffix = Path(source).suffix
        for companion in (f"y{suffix}.part", f".y{suffix}.lock"):
            shutil.copy(room / source, room / companion)
            result = softarm(*with_out(row, f"y{suffix}", (source, companion)), "--force", cwd=room, timeout=120)
            assert_one_line_error(result, companion, "is the input")
            assert (room / companion).read_bytes() == (room / source).read_bytes()
            (room / companion).unlink()
            assert not (room / f"y{suffix}").exists()
    assert digests(room, row.inputs) == before and left_behind(room) == []


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n, row in ROWS.items() if row.out])
def test_an_existing_part_of_the_output_is_kept_without_force(name, room):
    row = ROWS[name]
    (room / f"{row.out}.part").write_bytes(b"frames an earlier run kept")
    assert_one_line_error(softarm(*with_out(row, row.out), cwd=room, timeout=120), ".part", "--force")
    assert (room / f"{row.out}.part").read_bytes() == b"frames an earlier run kept"
    assert not (room / row.out).exists()


@pytest.mark.slow
@pytest.mark.parametrize("name,bad", [(n, b) for n, row in ROWS.items() for b in row.bad])
def test_a_number_out_of_range_is_refused_in_one_line_before_any_work(name, bad, room):
    row = ROWS[name]
    before = sorted(str(p) for p in room.rglob("*"))
    assert_one_line_error(softarm(*with_out(row, row.out or ""), *bad, cwd=room, timeout=120))
    assert sorted(str(p) for p in room.rglob("*")) == before


SIGNALS: dict[str, Callable[[subprocess.Popen], None]] = {
    "SIGINT": lambda p: p.send_signal(signal.SIGINT),
    "double SIGINT": lambda p: (p.send_signal(signal.SIGINT), time.sleep(0.05), p.send_signal(signal.SIGINT)),
    "SIGTERM": lambda p: p.send_signal(signal.SIGTERM),
}
AT_WORK = 3.5  # s after a command starts: Python, torch and Taichi loaded, the work under way


def at_work(process: subprocess.Popen, workers: bool) -> None:
    """Wait until the command works: its worker processes started (where it has them: the import segments frames in
    a pool), else AT_WORK seconds (Python, torch and Taichi loaded)."""
    if not workers:
        time.sleep(AT_WORK)
        return
    import psutil

    end = time.monotonic() + 30
    while time.monotonic() < end and process.poll() is None and not psutil.Process(process.pid).children():
        time.sleep(0.02)


def interrupted(args: list[str], folder: Path, how: str) -> tuple[int, str, float]:
    """(exit code, stderr, seconds it took to end) of the command, sent `how` once at work."""
    process = subprocess.Popen([SOFTARM, *args], cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    at_work(process, workers=args[0] == "import")
    if process.poll() is not None:
        return process.returncode, "ended before it could be interrupted: " + process.communicate()[1], 0.0
    SIGNALS[how](process)
    start = time.monotonic()
    try:
        _, err = process.communicate(timeout=90)
    except subprocess.TimeoutExpired:
        process.kill()
        return -9, "did not end within 90 s of the signal", 90.0
    return process.returncode, err, time.monotonic() - start


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n, row in ROWS.items() if row.long])
def test_an_interrupted_command_exits_130_says_so_keeps_its_inputs_and_leaves_no_lock(name, shared, tmp_path):
    """SIGINT, two SIGINTs 50 ms apart and SIGTERM, each to its own run of the command (the three run side by side)."""
    row = ROWS[name]
    rooms = {how: room_of(shared, tmp_path / how.replace(" ", "_")) for how in SIGNALS}
    inputs = [a for a in row.long if (shared / a).is_file()]
    with ThreadPoolExecutor(len(SIGNALS)) as pool:
        ends = dict(zip(SIGNALS, pool.map(lambda how: interrupted(row.long, rooms[how], how), SIGNALS)))
    for how, (code, err, took) in ends.items():
        lines = err.strip().splitlines()
        assert code == 130 and len(lines) == 1 and lines[0].startswith("interrupted"), (how, code, err)
        assert took < 60, (how, took)
        assert digests(rooms[how], inputs) == digests(shared, inputs), how
        assert [p for p in left_behind(rooms[how]) if p.endswith(".lock")] == [], how
