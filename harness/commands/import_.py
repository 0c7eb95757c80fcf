"""`untimely import FILE --interface FILE`: foreign traces loaded into the store."""
from __future__ import annotations

from dataclasses import dataclass

from harness.campaign import importing
from harness.commands import options

NAME = "import"
HELP = "load foreign traces (CSV, JSON lines, Parquet, ROS bags) into the store"


@dataclass(frozen=True)
class ImportRequest:
    file: str
    interface: str
    ros: str | None = None  # default: ros.toml beside the interface
    db: str = options.DEFAULT_DB_TEXT


Request = ImportRequest


def arguments(c) -> None:
    c.add_argument("file", help="a .csv, .jsonl or .parquet file with the events columns, or a ROS 1 .bag, a "
                                "rosbag2 folder (or its .mcap/.db3), or a folder of bags (docs/ros.md)")
    c.add_argument("--interface", required=True, help="interface description giving the reply classes")
    c.add_argument("--ros", help="a bag's mapping file (default: ros.toml beside the interface)")
    options.db(c)


def execute(request: ImportRequest) -> int:
    return importing.main(request.db, request.file, request.interface, request.ros)
