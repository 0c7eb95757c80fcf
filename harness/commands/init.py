"""`untimely init DIR`: a target folder that runs, written from an example, a GenoM3 description
or a ROS 2 graph."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from harness.campaign import from_bag
from harness.errors import UntimelyError
from harness.sut.ros2 import init as ros2_init
from harness.target import scaffold

NAME = "init"
HELP = "write a target folder that runs: interface, properties, golden mission, suts.toml and a standard-library adapter"


@dataclass(frozen=True)
class InitRequest:
    dir: str
    from_genom: str | None = None
    include: list[str] = field(default_factory=list)
    from_ros2: str | None = None
    from_bag: str | None = None
    interfaces: list[str] = field(default_factory=list)


Request = InitRequest


def arguments(c) -> None:
    c.add_argument("dir", help="the folder to write (created; existing files are never overwritten)")
    c.add_argument("--from-genom", metavar="FILE.gen", help="derive the interface and properties from a "
                   "GenoM3 component description")
    c.add_argument("--include", "-I", action="append", default=[], metavar="DIR",
                   help="with --from-genom: a folder #include searches, after the .gen file's own (repeatable)")
    c.add_argument("--from-ros2", metavar="COMMAND", help="derive the whole target (interface, ROS 2 mapping, SUTs "
                   "per installed distro, golden mission, properties) from the ROS 2 graph COMMAND brings up")
    c.add_argument("--from-bag", metavar="BAG", help="with --from-ros2: the golden mission is the session recorded in "
                   "this rosbag2 bag (MCAP or SQLite3, with service and action introspection)")
    c.add_argument("--interfaces", action="append", default=[], metavar="PKG_DIR",
                   help="with --from-ros2: your ROS 2 interface package (package.xml, action/, srv/, msg/), built "
                   "for every installed distro and found by the node, init and every SUT (repeatable, in build order)")


def execute(request: InitRequest) -> int:
    if request.from_bag and not request.from_ros2:
        raise UntimelyError(f"--from-bag {request.from_bag}: give --from-ros2 'COMMAND' too, the node(s) the bag was "
                            "recorded from (their graph gives the interface the bag's requests are read with)")
    if request.interfaces and not request.from_ros2:
        raise UntimelyError(f"--interfaces {request.interfaces[0]}: give --from-ros2 'COMMAND' too, the node(s) "
                            "that use these interfaces")
    if not request.from_ros2:
        return scaffold.scaffold(Path(request.dir), request.from_genom, request.include)
    if request.from_genom:
        raise UntimelyError("give --from-genom or --from-ros2, not both")
    if request.from_bag:
        if request.interfaces:
            raise UntimelyError("--interfaces with --from-bag is not supported yet: write the target with "
                                "--from-ros2 'COMMAND' --interfaces PKG_DIR alone, then edit its golden.mission")
        return from_bag.from_bag(Path(request.dir), request.from_ros2, request.from_bag)
    return ros2_init.from_ros2(Path(request.dir), request.from_ros2, interfaces=tuple(request.interfaces))
