"""`untimely init --from-ros2 COMMAND --from-bag BAG` (harness/campaign/from_bag.py): a recorded
nominal session as the golden mission. Without ROS: the mission text of hand-made requests, and
bad bags (written with rosbags' writer) refused naming the file and what is missing. With ROS 2
(skipped without `make ros2`): a session of examples/ros2 recorded by the bench's recorder on
Kilted, a target initialised from it, and a short campaign on both distros whose golden runs are
the bag's requests (the same session copied to SQLite3 gives the same golden)."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from rosbags.rosbag2 import Reader, StoragePlugin, Writer

from harness import ROOT
from harness.sut.ros2.environment import installed
from harness.cli import main as cli
from harness.errors import InputFileError
from harness.campaign.from_bag import golden_of, rosbag2
from harness.sut.bags.ros2_types import register, typestore
from harness.store.database import connect
from harness.target.interface import load_interface
from harness.target.ros2_graph import derive
from harness.target.ros2_texts import Recorded, recorded_golden_text, write
from harness.target.script import load_script

COMMAND = "python3 examples/ros2/sequencer.py"
TRIGGER = "---\nbool success\nstring message\n"
GRAPH = {"nodes": [{"name": "/seq", "actions": [
    {"name": "/seq/fib", "type": "test_msgs/action/Fibonacci", "fields": {"order": "int32"}}], "services": [
    {"name": "/seq/status", "type": "std_srvs/srv/Trigger", "fields": {},
     "response": {"success": "boolean", "message": "string"}},
    {"name": "/seq/get_parameters", "type": "rcl_interfaces/srv/GetParameters", "fields": {}, "response": {}}]}]}


def test_the_golden_mission_keeps_the_sessions_order_arguments_and_gaps(tmp_path):
    target = derive(COMMAND, GRAPH)
    text = recorded_golden_text(target, [
        Recorded(10.0, "seq.fib", {"order": "7"}, 10.5),
        Recorded(10.2, "seq.status", {}, 10.25),  # sent while fib ran: no wait before it
        Recorded(11.0, "seq.fib", None, None),  # after both replies; no arguments, no final in the bag
    ], "session")
    steps = [line for line in text.splitlines() if line and not line.startswith("#")]
    assert steps == ["send seq.fib order=7 as seq_fib_1", "sleep 0.2", "send seq.status as seq_status_1",
                     "wait seq_status_1 timeout=30", "wait seq_fib_1 timeout=30", "sleep 0.5",
                     "send seq.fib order=3 as seq_fib_2  # arguments not in the bag: the derived values"]
    write(tmp_path / "t", target, {"jazzy": ()}, tmp_path, text)
    load_script(tmp_path / "t" / "golden.mission", load_interface(tmp_path / "t" / "interface.toml"))


class Bag:
    """A rosbag2 bag written with rosbags' writer: a topic per call, one message each."""

    def __init__(self, path, plugin=StoragePlugin.MCAP):
        self.store, self.writer, self.path = typestore(), Writer(path, version=9, storage_plugin=plugin), path
        self.writer.open()

    def chatter(self) -> "Bag":
        string = self.store.types["std_msgs/msg/String"](data="hello")
        connection = self.writer.add_connection("/chatter", "std_msgs/msg/String", typestore=self.store)
        self.writer.write(connection, 1, self.store.serialize_cdr(string, "std_msgs/msg/String"))
        return self

    def trigger_call(self, service: str) -> "Bag":
        kind = "std_srvs/srv/Trigger_Event"
        register(self.store, kind, TRIGGER)
        types = self.store.types
        info = types["service_msgs/msg/ServiceEventInfo"](event_type=0, stamp=types["builtin_interfaces/msg/Time"](
            sec=1, nanosec=0), client_gid=np.zeros(16, dtype=np.uint8), sequence_number=1)
        event = types[kind](info=info, request=[types["std_srvs/srv/Trigger_Request"]()], response=[])
        connection = self.writer.add_connection(f"{service}/_service_event", kind, typestore=self.store,
                                                msgdef=TRIGGER, rihs01="RIHS01_" + "0" * 64)
        self.writer.write(connection, 1, self.store.serialize_cdr(event, kind))
        return self

    def close(self):
        self.writer.close()
        return self.path


@pytest.fixture
def draft(tmp_path):
    target = derive(COMMAND, GRAPH)
    write(tmp_path / "t", target, {"jazzy": ()}, tmp_path)
    return tmp_path / "t", target


def test_a_bag_without_introspection_is_refused_naming_it_and_what_is_missing(draft, tmp_path):
    bag = Bag(tmp_path / "chatter").chatter().close()
    with pytest.raises(InputFileError) as refused:
        golden_of(bag, *draft)
    for words in (str(bag), "no service or action introspection", "it records /chatter", "configure_introspection"):
        assert words in str(refused.value)


def test_a_bag_of_a_service_the_graph_lacks_is_refused(draft, tmp_path):
    bag = Bag(tmp_path / "other", StoragePlugin.SQLITE3).trigger_call("/seq/status").trigger_call("/arm/home").close()
    with pytest.raises(InputFileError) as refused:
        golden_of(bag, *draft)
    for words in (str(bag), "requests of /arm/home, which the graph of", "lacks", "/seq/status"):
        assert words in str(refused.value)


def test_a_bag_of_services_the_target_does_not_drive_only_is_refused(draft, tmp_path):
    bag = Bag(tmp_path / "parameters").trigger_call("/seq/get_parameters").close()
    with pytest.raises(InputFileError) as refused:
        golden_of(bag, *draft)
    for words in (str(bag), "holds requests of /seq/get_parameters only", "/seq/fib, /seq/fib/_action/cancel_goal, /seq/status"):
        assert words in str(refused.value)


def test_an_unreadable_or_missing_bag_is_refused(draft, tmp_path):
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "metadata.yaml").write_text("rosbag2_bagfile_information: [\n")
    with pytest.raises(InputFileError, match=f"(?s){broken}: cannot read the bag .*is it whole"):
        golden_of(broken, *draft)
    with pytest.raises(InputFileError, match=f"{tmp_path / 'gone'}: not found"):
        rosbag2(tmp_path / "gone")
    (tmp_path / "session.bag").write_bytes(b"#ROSBAG V2.0\n")
    with pytest.raises(InputFileError, match="session.bag: --from-bag takes one ROS 2 bag: a rosbag2 folder"):
        rosbag2(tmp_path / "session.bag")


def test_from_bag_needs_the_command_of_the_graph(tmp_path, capsys):
    assert cli(["init", str(tmp_path / "t"), "--from-bag", str(tmp_path)]) == 2
    assert "give --from-ros2 'COMMAND' too" in capsys.readouterr().err
    assert not (tmp_path / "t").exists()


# -- with ROS 2 ---------------------------------------------------------------------------------------
DISTROS = ("jazzy", "kilted")
ros2 = pytest.mark.skipif(any(installed(ROOT, d) for d in DISTROS),
                          reason="; ".join(filter(None, (installed(ROOT, d) for d in DISTROS))))
# the nominal session: its values (order 5 and 4) and its pauses differ from the derived golden's
NOMINAL = """send sequencer.configure as c
wait c timeout=30
send sequencer.activate as a
wait a timeout=30
sleep 1.5
send sequencer.fibonacci order=5 as f
send sequencer.status as s
wait all timeout=30
send sequencer.countdown order=4 as d
wait d timeout=30
send sequencer.reset as r
wait r timeout=30
send sequencer.deactivate as x
wait x timeout=30
send sequencer.shutdown as z
wait z timeout=30
"""
SENT = [("sequencer.configure", {}), ("sequencer.activate", {}), ("sequencer.fibonacci", {"order": 5}),
        ("sequencer.status", {}), ("sequencer.countdown", {"order": 4}), ("sequencer.reset", {}),
        ("sequencer.deactivate", {}), ("sequencer.shutdown", {})]


def harness(*args: str, timeout_s: float, env=None) -> subprocess.CompletedProcess:
    done = subprocess.run([sys.executable, "-m", "harness", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout_s, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    return done


def sqlite_copy(bag, out):
    """The MCAP bag `bag` as an SQLite3 bag, message for message."""
    with Reader(bag) as reader:
        writer = Writer(out, version=9, storage_plugin=StoragePlugin.SQLITE3)
        writer.open()
        made = {c.id: writer.add_connection(c.topic, c.msgtype, msgdef=c.msgdef.data, rihs01=c.digest)
                for c in reader.connections}
        for connection, at, raw in reader.messages():
            writer.write(made[connection.id], at, raw)
        writer.close()
    return out


def sent(con, trace_id: int) -> list[tuple[str, dict]]:
    rows = con.execute("""select module || '.' || service, args from events where trace_id = ? and kind = 'request'
                          order by rqst_id""", [trace_id]).fetchall()
    return [(service, {k: int(v) for k, v in json.loads(args or "{}").items()}) for service, args in rows]


@pytest.mark.slow
@ros2
def test_a_recorded_session_is_the_golden_mission_of_a_campaign_that_runs(tmp_path):

    first = tmp_path / "first"
    harness("init", str(first), "--from-ros2", COMMAND, timeout_s=120)
    (first / "nominal.mission").write_text(NOMINAL)
    bags = tmp_path / "bags"
    harness("run", str(first / "nominal.mission"), "--sut", "sequencer-kilted", "--db", str(tmp_path / "rec.duckdb"),
            timeout_s=180, env={**os.environ, "UNTIMELY_ROSBAG": str(bags)})
    bag = next(bags.iterdir())
    recorded = sent(connect(tmp_path / "rec.duckdb", read_only=True), 1)
    assert recorded == SENT, "the recorded run sent the nominal session"
    folder = tmp_path / "from-bag"
    harness("init", str(folder), "--from-ros2", COMMAND, "--from-bag", str(bag), timeout_s=120)
    golden = (folder / "golden.mission").read_text()
    # the session's pause before fibonacci, 1.5 s, as the bag timed it: from the activate's final
    # reply to the next send, which a loaded machine lengthens (1.72 s seen in a full run beside a busy loop)
    pause = float(re.search(r"sleep ([\d.]+)\nsend sequencer\.fibonacci", golden)[1])
    assert 1.4 <= pause < 3.0, golden
    sqlite = tmp_path / "from-sqlite"
    harness("init", str(sqlite), "--from-ros2", COMMAND, "--from-bag", str(sqlite_copy(bag, tmp_path / "db3")),
            timeout_s=120)
    steps = lambda text: [line for line in text.splitlines() if not line.startswith("#")]  # noqa: E731
    assert steps((sqlite / "golden.mission").read_text()) == steps(golden), "the same session read from SQLite3"
    db = tmp_path / "campaign.duckdb"
    harness("campaign", "--mission", str(folder), "--strategy", "focused", "--budget", "20s", "--sut",
            ",".join(f"sequencer-{d}" for d in DISTROS), "--jobs", "2", "--db", str(db), timeout_s=420)
    con = connect(db, read_only=True)
    goldens = con.execute("""select sut, outcome, trace_id from traces join scripts using (script_id)
                             where kind = 'golden' order by sut""").fetchall()
    assert [(sut, outcome) for sut, outcome, _ in goldens] == [(f"sequencer-{d}", "completed") for d in DISTROS]
    for _, _, trace_id in goldens:
        assert sent(con, trace_id) == SENT, "the golden run sends the bag's requests, in its order, with its values"
