"""Bags as traces (docs/ros.md, "Judging a bag"): a ROS 1 .bag, a ROS 2 rosbag2 folder (MCAP or
SQLite3), or a folder of them, read with the `rosbags` library (no ROS needed). One bag is one
trace, labelled with its file name; the mapping file (ros.toml) says which topics carry which
service. The bag's receive stamps are the observed timeline (`events`); the SUT's own stamps (ROS 1
headers; ROS 2 the server's introspection events and goals' accept stamps) the SUT's clock
(`internal_events`, as an external SUT's `internal` messages; timeline.sut_rows).
"""
from __future__ import annotations

import sys
from pathlib import Path

import pyarrow as pa

from harness.sut.roscommon.mapping import load_mapping
from harness.errors import InputFileError, UntimelyError
from harness.sut.bags.routes import Routes
from harness.target.interface import Interface
from harness.target.mission import ROS_MAPPING_FILE
from harness.trace import IMPORTED_COLUMNS

BAG_SUFFIXES = (".bag", ".mcap", ".db3")
COLUMNS = IMPORTED_COLUMNS


def is_bag(path: Path) -> bool:
    return path.suffix.lower() in BAG_SUFFIXES or path.is_dir()


def _rosbag2_folder(path: Path) -> Path | None:
    """The rosbag2 folder (with its metadata.yaml) that `path` is or is in."""
    for folder in (path, path.parent):
        if folder.is_dir() and (folder / "metadata.yaml").is_file():
            return folder
    return None


def bags(path: Path) -> list[Path]:
    """The bags `path` names: itself, or every bag in a folder of bags."""
    if not path.exists():
        raise InputFileError(path, "", "not found; pass a .bag file, a rosbag2 folder, its .mcap or .db3, "
                             "or a folder of bags")
    if path.suffix.lower() == ".bag" or _rosbag2_folder(path):
        return [path]
    if path.is_dir():
        for active in sorted(path.glob("*.bag.active")):
            print(f"{active}: left out, a bag still being written or never closed (`rosbag reindex` closes it)",
                  file=sys.stderr)
        found = sorted(p for p in path.iterdir() if p.suffix.lower() == ".bag" or _rosbag2_folder(p) == p)
        if found:
            return found
        raise InputFileError(path, "", "is a folder that holds no bag (.bag files or rosbag2 folders with a "
                             "metadata.yaml); pass a .csv, .jsonl or .parquet file, a bag, or a folder of bags")
    raise InputFileError(path, "", f"{path.name} is not inside a rosbag2 folder (no metadata.yaml beside it); "
                         "pass the folder that rosbag2 recorded")


def mapping_for(interface: Interface, ros: str | None):
    """The mapping file given, else ros.toml beside the interface."""
    path = Path(ros) if ros else Path(interface.path).with_name(ROS_MAPPING_FILE)
    if not ros and not path.is_file():
        raise InputFileError(path, "", "no mapping file beside the interface; pass --ros FILE (docs/ros.md)")
    return load_mapping(path)


def _read_one(bag: Path, routes: Routes):
    from rosbags.highlevel import AnyReaderError  # imported here: rosbags loads its type stores
    from rosbags.rosbag1 import ReaderError as Ros1Error
    from rosbags.rosbag2 import ReaderError as Ros2Error
    from rosbags.serde import SerdeError
    from rosbags.typesys import TypesysError

    from harness.sut.bags.ros1 import read_ros1
    from harness.sut.bags.ros2 import read_ros2
    try:
        timeline, notes = read_ros1(bag, routes) if bag.suffix.lower() == ".bag" else \
            read_ros2(_rosbag2_folder(bag), routes)
        return timeline, notes + timeline.finish()
    except UntimelyError as e:
        raise InputFileError(bag, "", str(e)) from None
    except (AnyReaderError, Ros1Error, Ros2Error, SerdeError, TypesysError, ValueError) as e:
        raise InputFileError(bag, "", f"cannot read the bag ({type(e).__name__}: {e}); is it whole? "
                             "(`rosbag reindex` repairs a ROS 1 bag left .active)") from None


def read_bags(path: Path, interface: Interface, ros: str | None = None) -> tuple[pa.Table, str, pa.Table]:
    """Every bag's events as the importer's text columns, plus `line` (the event's number); and the
    events on the SUT's clock, in the same columns (without outcome and sut)."""
    routes = Routes(interface, mapping_for(interface, ros))
    rows, sut_rows = [], []
    for bag in bags(path):
        timeline, notes = _read_one(bag, routes)
        for note in notes:
            print(f"{bag}: {note}", file=sys.stderr)
        if timeline.orphans:
            print(f"{bag}: {timeline.orphans} replies to goals whose request the bag does not hold were left out "
                  "(the recording started after them)", file=sys.stderr)
        events = timeline.rows(bag.name)
        if not events:
            raise InputFileError(bag, "", f"no request of the interface in this bag; the mapping "
                                 f"{routes.mapping.path} names {', '.join(sorted({r.name for r in routes.by_service.values()}))}")
        rows += [{**event, "outcome": "completed", "sut": bag.name} for event in events]
        sut_rows += timeline.sut_rows(bag.name)
    return _table(rows, COLUMNS), "event", _table(sut_rows, COLUMNS[:-2])


def _table(rows: list[dict], columns: tuple[str, ...]) -> pa.Table:
    table = {name: pa.array([None if row[name] is None else str(row[name]) for row in rows], pa.string())
             for name in columns}
    return pa.table({"line": pa.array(range(1, len(rows) + 1), pa.int64()), **table})
