"""Which reader a robot's log needs, told by its own bytes rather than its name: MCAP (ROS 2 or Foxglove), a ROS 1
`.bag`, or a ROS 2 bag (a folder with `metadata.yaml` and its `.db3` or `.mcap` files). Anything else is refused in
one line that says what the file looks like."""

from pathlib import Path

from softarm.errors import RecordingError
from softarm.real.log import LogFile
from softarm.record.reader import MCAP_MAGIC

ROS1_MAGIC = b"#ROSBAG V2.0\n"
SQLITE_MAGIC = b"SQLite format 3\x00"
LOOKS_LIKE = ((b"\x89PNG", "a PNG image"), (b"\xff\xd8\xff", "a JPEG image"), (b"PK\x03\x04", "a zip archive"),
              (b"\x1f\x8b", "a gzip file"), (b"\x28\xb5\x2f\xfd", "a zstd file"), (b"#ROSBAG", "a ROS 1 bag of an "
              "older version than 2.0"), (b"\x93NUMPY", "a NumPy array"), (b"%PDF", "a PDF"))
FORMATS = "an MCAP file, a ROS 1 .bag or a ROS 2 bag folder (metadata.yaml with .db3 or .mcap files)"


def open_log(path: Path) -> LogFile:
    """The log at `path`, opened by the reader its format needs."""
    path = Path(path)
    if path.is_dir():
        if not (path / "metadata.yaml").is_file():
            raise RecordingError(f"{path} is a folder without metadata.yaml, not a ROS 2 bag; softarm reads {FORMATS}")
        return _bag(path)
    try:
        with open(path, "rb") as f:
            head = f.read(64)
    except FileNotFoundError:
        raise RecordingError(f"log {path} not found") from None
    except OSError as e:
        raise RecordingError(f"log {path} cannot be read ({e.strerror})") from None
    if head.startswith(MCAP_MAGIC):
        from softarm.real.mcap_log import McapLog

        return McapLog(path)
    if head.startswith(ROS1_MAGIC):
        return _bag(path)
    if head.startswith(SQLITE_MAGIC):
        if (path.parent / "metadata.yaml").is_file():
            return _bag(path.parent)
        raise RecordingError(f"{path} is an SQLite file without the metadata.yaml of a ROS 2 bag beside it; give the "
                             "bag's folder (ros2 bag record writes both)")
    raise RecordingError(f"{path} is {looks_like(head)}, not a log softarm reads; it reads {FORMATS}")


def log_inputs(path: Path) -> list[Path]:
    """Every path the log at `path` is read from (a ROS 2 bag folder: the folder and each of its files), so that no
    output may replace one of them."""
    path = Path(path)
    return [path, *sorted(p for p in path.rglob("*") if p.is_file())] if path.is_dir() else [path]


def looks_like(head: bytes) -> str:
    """What the first bytes of a file suggest it is, for the refusal."""
    if not head:
        return "empty"
    found = next((name for magic, name in LOOKS_LIKE if head.startswith(magic)), None)
    if found is not None:
        return found
    for cut in range(4):  # the 64 bytes may end inside a character
        try:
            text = head[:len(head) - cut].decode("utf-8")
        except UnicodeDecodeError:
            continue
        if text.isprintable() or all(c.isprintable() or c.isspace() for c in text):
            return "a text file" + (" (JSON?)" if text.lstrip().startswith(("{", "[")) else "")
        break
    return "a binary file of no format softarm knows"


def _bag(path: Path) -> LogFile:
    from softarm.real.bag_log import BagLog

    return BagLog(path)
