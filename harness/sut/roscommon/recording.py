"""Where a run's bag goes: `run`/`campaign --rosbag DIR` put DIR in $UNTIMELY_ROSBAG, which the ROS 1
launcher (harness/sut/ros/__main__.py) and the ROS 2 one (harness/sut/ros2/serve.py) read."""
from __future__ import annotations

import os

ROSBAG_ENV = "UNTIMELY_ROSBAG"


def recording_folder() -> str | None:
    return os.environ.get(ROSBAG_ENV) or None
