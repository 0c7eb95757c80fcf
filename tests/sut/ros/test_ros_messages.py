"""Message classes of typed routes (harness/sut/ros/messages.py), under Debian's ROS Python:
an action of a package Debian lacks, generated from its .action text (with a dependency on
Debian's geometry_msgs), filled from a request's arguments and the route's defaults."""
import json
import subprocess

import pytest

from tests.support.ros_driver import ensure_ros_venv, requires_ros

pytestmark = [requires_ros, pytest.mark.slow]

PROBE = """
import json, sys
from pathlib import Path
from harness.sut.ros.messages import action_classes, fill
from harness.sut.roscommon.routes import Route
from harness.errors import UntimelyError
route = Route("action", "/dock", "dock_msgs/Dock", {"x": "pose.position.x", "speed": "speed", "slow": "slow"},
              {"pose.orientation.w": 1.0}, code="code", definition="Dock.action")
classes = action_classes(route, Path(sys.argv[1]))
goal = fill(classes.Goal(), route, {"x": "3.5", "speed": 0.2, "slow": "true"})
problems = []
for args in ({"y": 1}, {"x": "abc"}):
    try:
        fill(classes.Goal(), route, args)
    except UntimelyError as e:
        problems.append(str(e))
print(json.dumps({"goal": [goal.pose.position.x, goal.speed, goal.slow, goal.pose.orientation.w],
                  "result": classes.Result.__slots__, "type": classes.Action._type, "problems": problems}))
"""


def test_an_action_debian_lacks_is_generated_from_its_text_and_filled(tmp_path):
    (tmp_path / "Dock.action").write_text("geometry_msgs/Pose pose\nfloat64 speed\nbool slow\n---\nstring code\n"
                                          "---\nfloat64 progress\n")
    python = ensure_ros_venv()
    out = subprocess.run([str(python), "-c", PROBE, str(tmp_path)], capture_output=True, text=True, check=True)
    found = json.loads(out.stdout)
    assert found["goal"] == [3.5, 0.2, True, 1.0]  # text and JSON values converted to the fields' types
    assert found["result"] == ["code"] and found["type"] == "dock_msgs/DockAction"
    assert found["problems"] == [
        "argument y=1 has no field in dock_msgs/Dock; add it to the route's fields in ros.toml",
        "'abc' cannot fill dock_msgs/Dock field pose.position.x, a float64"]


SERVICE_PROBE = """
import json, sys
from pathlib import Path
import roscpp.srv, std_srvs.srv
from harness.sut.ros.messages import fill, service_class
from harness.sut.roscommon.routes import Route
folder = Path(sys.argv[1])
made = {name: service_class(Route("service", "/s", f"made_srvs/{name}", definition=f"{name}.srv"), folder)
        for name in ("Trigger", "SetBool", "GetLoggers", "Dock")}
debian = {"Trigger": std_srvs.srv.Trigger, "SetBool": std_srvs.srv.SetBool, "GetLoggers": roscpp.srv.GetLoggers}
dock = Route("service", "/dock", "made_srvs/Dock", {"x": "pose.position.x"}, definition="Dock.srv")
request = fill(made["Dock"]._request_class(), dock, {"x": "2.5"})
response = made["Dock"]._response_class(code="ok", success=True)
print(json.dumps({"md5": {name: [made[name]._md5sum, kind._md5sum] for name, kind in debian.items()},
                  "type": made["Dock"]._type, "x": request.pose.position.x,
                  "response": [made["Dock"]._response_class._type, response.code, response.success]}))
"""


def test_a_service_debian_lacks_is_generated_from_its_srv_text(tmp_path):
    """A .srv file gives the request and response classes and the service's MD5 sum, which is what
    catkin would build: the same text as Debian's std_srvs and roscpp services gives their sums
    (GetLoggers' response holds roscpp/Logger[], a type of another package)."""
    for name, text in (("Trigger", "---\nbool success\nstring message\n"), ("SetBool", "bool data\n---\nbool success\n"
                       "string message\n"), ("GetLoggers", "---\nroscpp/Logger[] loggers\n"),
                       ("Dock", "geometry_msgs/Pose pose\n---\nstring code\nbool success\n")):
        (tmp_path / f"{name}.srv").write_text(text)
    python = ensure_ros_venv()
    out = subprocess.run([str(python), "-c", SERVICE_PROBE, str(tmp_path)], capture_output=True, text=True, check=True)
    found = json.loads(out.stdout)
    assert all(made == debian for made, debian in found["md5"].values()), found["md5"]
    assert found["type"] == "made_srvs/Dock" and found["x"] == 2.5
    assert found["response"] == ["made_srvs/DockResponse", "ok", True]
