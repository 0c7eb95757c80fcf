"""Speed of `import` on bags (harness/sut/bags): a ROS 1 .bag and a ROS 2 MCAP bag of the same
N goals (request, feedback, final each), written with rosbags' writer by the tests' bag writers,
against the same events imported from CSV. Printed as events/s and as the ratio to CSV, which the
machine's load affects alike."""
from __future__ import annotations

import csv
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rosbags.rosbag2 import StoragePlugin  # noqa: E402

from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.store.bench_reads import event_count, events_in_order  # noqa: E402
from harness.store.database import connect  # noqa: E402
from harness.campaign.importing import import_path  # noqa: E402
from harness.target.interface import load_interface  # noqa: E402
from harness.trace import EVENT_COLUMNS  # noqa: E402
from tests import test_ros_bag1_reader as ros1, test_ros_bags2 as ros2  # noqa: E402

GOALS = 3000


def ros1_bag(path: Path) -> Path:
    bag = ros1.Bag(path)
    for n in range(GOALS):
        bag.goal(10.0 + n, f"g{n}", "GotoPosition", x=9.0, y=4.0)
        bag.feedback(10.1 + n, f"g{n}")
        bag.result(10.5 + n, f"g{n}", ros1.ABORTED, "goal_unreachable")
    bag.close()
    return path


def ros2_bag(path: Path) -> Path:
    bag = ros2.Bag(path, StoragePlugin.MCAP)
    for n in range(GOALS):
        at = ros2.BASE + n
        bag.send_goal(at, n, 9.0, 4.0, True)
        bag.feedback(at + 0.1, n)
        bag.result(at + 0.6, n, ros2.ABORTED, "goal_unreachable")
    bag.close()
    return path


def timed(path: Path, interface, **options) -> tuple[float, int]:
    con = connect(":memory:")
    start = time.perf_counter()
    import_path(con, path, interface, **options)
    wall = time.perf_counter() - start
    return wall, event_count(con)


def as_csv(bag: Path, interface, out: Path, **options) -> Path:
    con = connect(":memory:")
    import_path(con, bag, interface, **options)
    rows = events_in_order(con, EVENT_COLUMNS, "bag")
    with out.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["trace_id", *EVENT_COLUMNS])
        writer.writerows(rows.fetchall())
    return out


def main() -> int:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        mapping = folder / "ros.toml"
        mapping.write_text((DEFAULT_MISSION_DIR / "ros.toml").read_text())
        bags = [("ROS 1 .bag", ros1_bag(folder / "day.bag"), {}),
                ("ROS 2 MCAP", ros2_bag(folder / "day2"), {"ros": str(ros2.MAPPING)})]
        print(f"{GOALS} goals per bag; import wall time (in-memory store)")
        print(f"{'source':<12} {'events':>7} {'wall s':>7} {'events/s':>9} {'vs CSV':>7}")
        for name, bag, options in bags:
            csv_wall, _ = timed(as_csv(bag, interface, folder / f"{bag.stem}.csv", **options), interface)
            wall, events = timed(bag, interface, **options)
            print(f"{name:<12} {events:7} {wall:7.2f} {events / wall:9,.0f} {wall / csv_wall:6.1f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
