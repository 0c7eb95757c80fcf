"""The recorder's wait for its connections (harness/sut/ros/recorder.py), against a stand-in
for the master and a publishing node on XML-RPC: no ROS needed. The live recording is in
test_ros_bags1.py."""
import threading
from types import SimpleNamespace
from xmlrpc.server import SimpleXMLRPCServer

import pytest

from harness.errors import ChildError
from harness.sut.ros.recorder import wait_connected


@pytest.fixture
def ros_graph():
    """A master whose node /sut publishes /a/goal and /a/result; /sut has accepted the recorder on /a/goal."""
    server = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
    uri = f"http://127.0.0.1:{server.server_address[1]}"
    publishers = [["/a/goal", ["/sut"]], ["/a/result", ["/sut"]]]
    server.register_function(lambda caller: [1, "", [publishers, [], []]], "getSystemState")
    server.register_function(lambda caller, node: [1, "", uri], "lookupNode")
    server.register_function(lambda caller: [1, "", [[1, "/untimely_record", "o", "TCPROS", "/a/goal", True, ""],
                                                     [2, "/other", "o", "TCPROS", "/a/result", True, ""]]],
                             "getBusInfo")
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield {"ROS_MASTER_URI": uri}
    server.shutdown()
    server.server_close()


def test_a_recorder_not_connected_in_time_ends_the_run_naming_what_it_lacks(ros_graph):
    recorder = SimpleNamespace(failure=lambda: None)
    with pytest.raises(ChildError, match=r"rosbag record was not connected within 0.3 s to /a/result from /sut, "
                                         r"/w \(no publisher\); the machine may be overloaded"):
        wait_connected(recorder, ["/a/goal", "/a/result", "/w"], ros_graph, 0.3)
    wait_connected(recorder, ["/a/goal"], ros_graph, 0.3)  # connected: returns at once


def test_a_recorder_that_died_is_named_with_its_last_lines(ros_graph):
    recorder = SimpleNamespace(failure=lambda: "the rosbag exited with status 1; its last lines: boom")
    with pytest.raises(ChildError, match="the rosbag exited with status 1; its last lines: boom"):
        wait_connected(recorder, ["/a/result"], ros_graph, 30)
