"""A ROS 2 run recorded to an MCAP bag (harness/sut/ros2/recorder.py) imports with the project's
ROS 2 bag reader (harness/sut/bags/ros2.py) to the exchange that happened: tests/support/ros2_peer.py's
call of ndd.SetParams and goal of ndd.GotoPosition, mapped by tests/bags/ros2_recording.toml."""
import json
import signal
import subprocess
from pathlib import Path

import pytest
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from harness import ROOT
from harness.sut.ros2.environment import DISTROS, Ros2Environment, installed
from harness.store.database import connect
from harness.campaign.importing import import_path
from tests.support.paths import BAGS, SUPPORT

pytestmark = pytest.mark.slow

PEER, MAPPING = SUPPORT / "ros2_peer.py", BAGS / "ros2_recording.toml"
TIMEOUT_S = 60
# untimely_msgs/Call is generic: its arguments are the request's JSON, as the goal's are
CALL = [("request", "ndd.SetParams", {"speed": 0.5}, None), ("final", "ndd.SetParams", None, "ok")]
GOAL = [("request", "ndd.GotoPosition", {"x": 3.0, "y": 4.0}, None),
        ("intermediate", "ndd.GotoPosition", None, None), ("final", "ndd.GotoPosition", None, "ok")]
# Jazzy's actions have no introspection: a generic goal names its service only in the goal itself,
# which only send_goal's events carry, so its goals are not in the trace (docs/ros2.md, "Recording").
EXPECTED = {"jazzy": CALL, "kilted": GOAL + CALL}  # by service name


def record(ros: Ros2Environment, bag: Path) -> dict:
    """The peers' exchange, recorded by the recorder in a process of its own; the client's replies."""
    server = subprocess.Popen([str(ros.python), str(PEER), "serve", "untimely_server"], env=ros.env,
                              stdout=subprocess.PIPE, text=True)
    recorder = None
    try:
        assert server.stdout.readline().strip() == "ready"
        recorder = subprocess.Popen([str(ros.python), "-m", "harness.sut.ros2.recorder", str(bag),
                                     "--action", "/dala/ndd=untimely_msgs/action/Request",
                                     "--service", "/ndd/set_params=untimely_msgs/srv/Call"],
                                    env=ros.env, stdout=subprocess.PIPE, text=True, cwd=ROOT)
        assert recorder.stdout.readline().strip() == "recording"
        client = subprocess.run([str(ros.python), str(PEER), "call", "recorded"], env=ros.env,
                                capture_output=True, text=True, timeout=TIMEOUT_S)
        assert client.returncode == 0, client.stderr[-3000:]
        return json.loads(client.stdout)
    finally:
        stopped = [(process, signum) for process, signum in ((recorder, signal.SIGINT), (server, signal.SIGTERM))
                   if process is not None]
        for process, signum in stopped:
            process.send_signal(signum)
        # every process is waited for before any exit status is judged: none is left behind
        codes = [(process.args[2:4], process.wait(timeout=TIMEOUT_S)) for process, _ in stopped]
        assert all(code == 0 for _, code in codes), codes


def imported(bag: Path, interface) -> list[tuple]:
    con = connect(":memory:")
    import_path(con, bag, interface, str(MAPPING))
    rows = con.execute("select kind, module || '.' || service, args::varchar, reply from events order by seq").fetchall()
    return [(kind, service, json.loads(args) if args else None, reply) for kind, service, args, reply in rows]


@pytest.mark.parametrize("distro", DISTROS)
def test_a_recorded_run_imports_to_the_exchange_that_happened(tmp_path, interface, distro):
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    bag = tmp_path / "run"
    with Ros2Environment(ROOT, distro, slot=0) as ros:
        replies = record(ros, bag)
    assert (replies["code"], replies["goal"]) == ("ok", "ok")
    assert list(bag.glob("*.mcap")) and (bag / "metadata.yaml").is_file()
    # Each service's rows in their order; between services, the order is the recorder's receive
    # order of different topics, which may differ by a few milliseconds from the order of events.
    assert sorted(imported(bag, interface), key=lambda row: row[1]) == EXPECTED[distro]
    stored, announced = status_definition_hashes(bag)
    assert stored == announced and announced.startswith("RIHS01_") and announced != "RIHS01_" + "0" * 64


def status_definition_hashes(bag: Path) -> tuple[str, str]:
    """The hash of the status topic's stored definition (with the messages it uses), and the hash
    its publisher announced: equal when the definition is the one the node was built with."""
    with Reader(bag) as reader:
        status = next(c for c in reader.connections if c.topic.endswith("/_action/status"))
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(status.msgdef.data, status.msgtype))
    return store.hash_rihs01(status.msgtype), status.digest


def test_a_malformed_topic_argument_is_refused_naming_it_and_the_form(tmp_path):
    if installed(ROOT, DISTROS[0]):
        pytest.skip(installed(ROOT, DISTROS[0]))
    with Ros2Environment(ROOT, DISTROS[0], slot=0) as ros:
        done = subprocess.run([str(ros.python), "-m", "harness.sut.ros2.recorder", str(tmp_path / "bag"),
                               "--service", "ndd/set_params=Call"], env=ros.env, capture_output=True, text=True,
                              timeout=TIMEOUT_S, cwd=ROOT)
    assert done.returncode != 0 and "Traceback" not in done.stderr
    assert "'ndd/set_params=Call'" in done.stderr and "/NAME=package/kind/Type" in done.stderr
    assert not (tmp_path / "bag").exists()
