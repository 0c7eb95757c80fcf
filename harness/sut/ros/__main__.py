"""One run of a ROS 1 SUT on stdio: a rosmaster of its own, the SUT's node, and the adapter.

    python -m harness.sut.ros --mapping missions/dala/ros.toml -- NODE COMMAND ...

Order: the master starts on a free loopback port; the bench's hello gives the time scale, passed
to the node as $UNTIMELY_TIME_SCALE (with $ROS_MASTER_URI); once every mapped action server
answers (and, with --rosbag, every publisher has accepted the recorder), the hello is answered and
requests flow. When the mapping names a `reset_service` (and nothing is recorded), the hello
answer offers `reuse`: on `bye`, the node is reset through that service, bye is answered, and the
next hello starts the next run on the same master and node, with none of their start-up. On
end of input, SIGTERM, or `bye` without reuse, the node and the master are stopped and the ROS
log folder removed. A failure is an `error` line.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys

from harness.sut.roscommon.lines import LineWriter, read_hello, run_main, serve_runs
from harness.sut.roscommon.mapping import interface_services, load_mapping
from harness.sut.processes import Child, stop_all
from harness.sut.ros.master import ros_home, start_master
from harness.sut.ros.recorder import recorded_topics, start_recorder, stop_recorder, wait_connected
from harness.sut.roscommon.recording import recording_folder
from harness.errors import UntimelyError
from harness.sut.protocol import PROTO

def reset(service: str, timeout_s: float) -> bool:
    """The node back to its initial state, through its std_srvs/Trigger `service` (True: done)."""
    import rospy
    from std_srvs.srv import Trigger
    try:
        rospy.wait_for_service(service, timeout_s)
        answer = rospy.ServiceProxy(service, Trigger)()
    except (rospy.ROSException, rospy.ServiceException) as e:
        raise UntimelyError(f"the node's reset service {service} failed: {e}") from None
    if not answer.success:
        raise UntimelyError(f"the node's reset service {service} refused: {answer.message}")
    return True


def node_environment(mapping, hello: dict) -> dict[str, str]:
    """What a node learns from the launcher: the time scale; for a node that hands requests on to a
    layer of its own (cpp/dala_forward_node.cpp), the bench's hello, the routes, one a line:
    KIND NAME TYPE module.Service, and the reset service to serve (empty: none)."""
    routes = mapping.routes(interface_services(hello["interface"]))
    return {"UNTIMELY_TIME_SCALE": repr(hello["time_scale"]),
            "UNTIMELY_HELLO": json.dumps(hello, separators=(",", ":")),
            "UNTIMELY_ROUTES": "\n".join(f"{r.kind} {r.name} {r.type} {q}" for q, r in routes.items()),
            "UNTIMELY_RESET_SERVICE": mapping.reset_service or ""}


def run(args, out: LineWriter) -> None:
    mapping = load_mapping(args.mapping)
    children: list[Child] = []
    recorder = None
    home = ros_home()
    ros_up = False
    try:
        master, env = start_master(home, args.startup_timeout)
        children.append(master)
        hello = read_hello(sys.stdin)
        if hello is None:
            return
        time_scale = hello["time_scale"]
        if recording_folder():
            topics = recorded_topics(mapping, interface_services(hello["interface"]))
            recorder = start_recorder(recording_folder(), hello["run"], topics, env)
        node = Child("node", args.node, {**env, **node_environment(mapping, hello)})
        children.append(node)
        os.environ.update(env)
        import rospy  # only now: rospy reads the master's address from the environment

        from harness.sut.ros.adapter import Ros1Adapter
        rospy.init_node("untimely_adapter", disable_signals=True, disable_rosout=True)
        ros_up = True
        adapter = Ros1Adapter(mapping, hello["interface"], time_scale, out.write)

        def ready() -> None:
            adapter.wait_for_servers(args.startup_timeout, node.failure)
            if recorder:
                wait_connected(recorder, topics, env, args.startup_timeout)

        def greet(runs: int, offers: list[str]) -> None:
            adapter.hello(PROTO, f"ROS 1 actionlib adapter (master {env['ROS_MASTER_URI']}; node: "
                                 f"{' '.join(args.node)}; run {runs} of this master)", offers)

        reusable = mapping.reset_service is not None and not recorder
        serve_runs(adapter, hello, node, ready, greet,
                   (lambda: reset(mapping.reset_service, args.startup_timeout)) if reusable else None)
    finally:
        if recorder:
            stop_recorder(recorder)
        stop_all(children)
        if ros_up:
            rospy.signal_shutdown("bye")
        shutil.rmtree(home, ignore_errors=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m harness.sut.ros", description=__doc__.split("\n\n")[0])
    parser.add_argument("--mapping", required=True, help="the ros.toml beside the interface")
    parser.add_argument("--startup-timeout", type=float, default=60.0,
                        help="seconds for the master and every action server to come up (default 60)")
    parser.add_argument("node", nargs="+", help="the SUT node's command, after --")
    args = parser.parse_args(argv)
    return run_main(run, args)


if __name__ == "__main__":
    sys.exit(main())
