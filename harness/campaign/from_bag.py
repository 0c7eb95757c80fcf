"""A recorded nominal session as a target's golden mission: `untimely init DIR --from-ros2 'COMMAND'
--from-bag BAG` (docs/ros2.md, "A recorded session as the golden mission").

The bag is a rosbag2 folder (MCAP or SQLite3) whose introspection topics (`NAME/_service_event`,
an action's `NAME/_action/send_goal/_service_event`) hold the session's requests. It is read as
`untimely import` reads a bag (harness/sut/bags), with the interface and mapping derived from
COMMAND's graph (harness/sut/ros2/init.py); its requests, in the order their client sent them,
with their instants, arguments and final replies, become the golden mission
(harness/target/ros2_texts.py, recorded_golden_text). It lives here, beside importing.py, as it
ties the two parts of harness/sut that may not import each other: the graph's reading and the bags'.
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from harness.errors import InputFileError
from harness.sut.bags import _rosbag2_folder, bags, read_bags
from harness.sut.ros2 import init
from harness.target.interface import load_interface
from harness.target.mission import INTERFACE_FILE, ROS2_MAPPING_FILE
from harness.target.ros2_graph import Ros2Target
from harness.target.ros2_texts import Recorded, recorded_golden_text

# the service or action whose requests an introspection topic carries
INTROSPECTED = re.compile(r"^(?P<name>.+?)(/_action/(send_goal|get_result|cancel_goal))?/_service_event$")
RECORD_HOW = ("record the session with introspection on (configure_introspection(clock, qos, "
              "ServiceIntrospectionState.CONTENTS) in the client or the server; `UNTIMELY_ROSBAG=DIR untimely run` "
              "records a run so) and the _service_event topics in the bag")


def from_bag(folder: Path, command: str, bag: str) -> int:
    """`untimely init FOLDER --from-ros2 COMMAND --from-bag BAG`: the graph's target with the bag's golden mission."""
    recorded = rosbag2(Path(bag))
    return init.from_ros2(folder, command, lambda draft, target: golden_of(recorded, draft, target))


def rosbag2(path: Path) -> Path:
    """The one rosbag2 folder `path` names (itself, or the folder of its .mcap or .db3 file)."""
    found = bags(path)
    folder = _rosbag2_folder(found[0]) if len(found) == 1 and found[0].suffix.lower() != ".bag" else None
    if folder is None:
        raise InputFileError(path, "", "--from-bag takes one ROS 2 bag: a rosbag2 folder (MCAP or SQLite3, with "
                             "its metadata.yaml) or its .mcap or .db3 file")
    return folder


def golden_of(bag: Path, draft: Path, target: Ros2Target) -> str:
    """The golden mission's text: the requests of `bag`, read with the target written to `draft`."""
    _check_topics(bag, target)
    table, _, _ = read_bags(bag, load_interface(draft / INTERFACE_FILE), str(draft / ROS2_MAPPING_FILE))
    rows = table.to_pylist()
    finals = {row["rqst_id"]: float(row["t"]) for row in rows if row["kind"] == "final"}
    requests = [Recorded(float(row["t"]), f"{row['module']}.{row['service']}", _texts(bag, row),
                         finals.get(row["rqst_id"]))
                for row in sorted((r for r in rows if r["kind"] == "request"), key=lambda r: int(r["rqst_id"]))]
    return recorded_golden_text(target, requests, str(bag))


def _check_topics(bag: Path, target: Ros2Target) -> None:
    """The bag must carry introspection, and only of services and actions the graph has."""
    from rosbags.rosbag2 import Reader, ReaderError  # imported here: rosbags loads its type stores
    try:
        with Reader(bag) as reader:
            counts = {c.topic: c.msgcount for c in reader.connections}
    except ReaderError as e:
        raise InputFileError(bag, "", f"cannot read the bag ({e}); is it whole?") from None
    introspected = {m["name"] for t, n in counts.items() if n and (m := INTROSPECTED.match(t))}
    if not introspected:
        raise InputFileError(bag, "", f"holds no service or action introspection (no NAME/_service_event topic with "
                             f"messages; it records {', '.join(sorted(counts)) or 'nothing'}), where the golden "
                             f"mission's requests come from: {RECORD_HOW}")
    graph = {e.name for node in target.nodes for e in (*node.services, *node.actions)}
    lacking = sorted(introspected - graph)
    if lacking:
        raise InputFileError(bag, "", f"holds requests of {', '.join(lacking)}, which the graph of {target.command!r} "
                             f"lacks (it has {', '.join(sorted(graph))}); give the command that starts the node(s) "
                             "the bag was recorded from")
    driven = {s.route.get("action") or s.route.get("service") for s in target.services}
    if not introspected & driven:
        raise InputFileError(bag, "", f"holds requests of {', '.join(sorted(introspected))} only, none of the "
                             f"services and actions the target drives ({', '.join(sorted(driven))}); record a "
                             "session that calls them")
    for name in sorted(introspected - driven):
        print(f"{bag}: the requests of {name} are left out: the target does not drive it (infrastructure)",
              file=sys.stderr)


def _texts(bag: Path, row: dict) -> dict[str, str] | None:
    """A request's arguments as a mission script writes them (5.0 as 5); None when the bag lacks them."""
    if row["args"] is None:
        return None
    texts = {}
    for name, item in json.loads(row["args"]).items():
        text = str(int(item)) if isinstance(item, float) and item.is_integer() else str(item)
        if not text or re.search(r"[\s#]", text):
            raise InputFileError(bag, "", f"request {row['rqst_id']} ({row['module']}.{row['service']}) carries "
                                 f"{name} = {item!r}, which a mission script cannot write (empty, or a space or #); "
                                 "edit golden.mission by hand after init without --from-bag")
        texts[name] = text
    return texts
