"""`untimely init DIR`: a target folder that runs, written from an example, a GenoM3 description
or a ROS 2 graph."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from harness.adapters.ros2 import init as ros2_init
from harness.errors import UntimelyError
from harness.target import scaffold

NAME = "init"
HELP = "write a target folder that runs: interface, properties, golden mission, suts.toml and a standard-library adapter"


@dataclass(frozen=True)
class Request:
    dir: str
    from_genom: str | None = None
    include: list[str] = field(default_factory=list)
    from_ros2: str | None = None


def arguments(c) -> None:
    c.add_argument("dir", help="the folder to write (created; existing files are never overwritten)")
    c.add_argument("--from-genom", metavar="FILE.gen", help="derive the interface and properties from a "
                   "GenoM3 component description")
    c.add_argument("--include", "-I", action="append", default=[], metavar="DIR",
                   help="with --from-genom: a folder #include searches, after the .gen file's own (repeatable)")
    c.add_argument("--from-ros2", metavar="COMMAND", help="derive the whole target (interface, ROS 2 mapping, SUTs "
                   "per installed distro, golden mission, properties) from the ROS 2 graph COMMAND brings up")


def execute(request: Request) -> int:
    if not request.from_ros2:
        return scaffold.scaffold(Path(request.dir), request.from_genom, request.include)
    if request.from_genom:
        raise UntimelyError("give --from-genom or --from-ros2, not both")
    return ros2_init.from_ros2(Path(request.dir), request.from_ros2)
