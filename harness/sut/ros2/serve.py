"""One slot's ROS 2 adapter process, under the distro's interpreter, in the environment the
launcher (__main__.py) made: it starts the SUT's node on the bench's hello, brings it up, and
serves run after run (docs/ros2.md). Not started by hand: `python -m harness.sut.ros2` does.

Order: the bench's hello gives the time scale, passed to the node as $UNTIMELY_TIME_SCALE; once
every mapped server and service answers, a lifecycle node has been configured and activated, and
the node has echoed a first ping, the hello is answered and requests flow; it names the services
whose servers publish introspection (`taken_services`: their requests may get `taken` replies).
With a lifecycle node the hello offers `reuse`: on `bye`, bye is answered and the node is reset
(deactivate, cleanup, configure, activate: a fresh layer), and the next hello starts the next run
on the same node; a node the mission drives itself (lifecycle = "mission") is taken back to
unconfigured instead, and when it cannot be (finalized, a request still unanswered) the adapter
ends and the bench starts a fresh one. With $UNTIMELY_ROSBAG set (a folder), the run's traffic is recorded into the MCAP
bag FOLDER/trace-ID (ID: the hello's run), once every recorded topic has its publisher, and reuse
is not offered. On end of input, SIGTERM, or `bye` without reuse, the node is stopped. A failure
is an `error` line.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from harness.sut.roscommon.lines import LineWriter, read_hello, run_main, serve_runs
from harness.sut.roscommon.mapping import check_cancels, load_mapping
from harness.sut.processes import Child, stop_all
from harness.sut.roscommon.recording import recording_folder
from harness.sut.protocol import PROTO

RECORDER_DRAIN_S = 1.0  # within the bench's 2 s of grace after bye
# How long a node the mission drove may take to answer its way back to unconfigured, and to end the
# ended run's goals: a fresh node's start-up (about a second) is the alternative.
TAKE_BACK_S = 2.0


def run(args, out: LineWriter) -> None:
    mapping = load_mapping(args.mapping)
    hello = read_hello(sys.stdin)
    if hello is None:
        return
    check_cancels(mapping, hello["interface"])  # before the node starts: a mapping it cannot serve is refused
    started = time.monotonic()
    node = Child("node", args.node, {**os.environ, "UNTIMELY_TIME_SCALE": repr(hello["time_scale"])})
    adapter = recorder = None
    try:
        import rclpy  # only here: the launcher's environment is what makes it importable

        from harness.sut.ros2.adapter import Ros2Adapter
        from harness.sut.ros2.lifecycle import BRING_UP, RESET
        rclpy.init(signal_handler_options=rclpy.signals.SignalHandlerOptions.NO)
        adapter = Ros2Adapter(mapping, hello["interface"], hello["time_scale"], out.write)
        adapter.wait_for_servers(args.startup_timeout, node.failure)
        discovery = time.monotonic() - started  # the node's start-up and its discovery by the adapter
        if recording_folder():  # one bag per run, so no reuse
            recorder = adapter.record(Path(recording_folder()) / f"trace-{hello['run']}", args.startup_timeout)
        if mapping.lifecycle is True:
            adapter.transition(BRING_UP, args.startup_timeout)
        adapter.start_probing()
        taken_services = adapter.find_introspection()

        def ready() -> None:
            if mapping.ping_topic:
                adapter.wait_echo(args.startup_timeout, node.failure)

        def greet(runs: int, offers: list[str]) -> None:
            adapter.hello(PROTO, f"ROS 2 {os.environ.get('UNTIMELY_ROS2_DISTRO', '')} adapter (domain "
                                 f"{os.environ.get('ROS_DOMAIN_ID')}; node: {' '.join(args.node)}; up in {discovery:.2f} s; run {runs} of "
                                 "this node)", offers, taken_services)

        def reset() -> bool:
            adapter.transition(RESET, args.startup_timeout)
            return True

        def take_back() -> bool:
            """The node as a fresh one starts (unconfigured, nothing of the ended run unanswered), else
            False: this adapter ends, and the bench starts a fresh node for the next run."""
            why = adapter.lifecycle.unconfigure(TAKE_BACK_S)
            if why is None and (unanswered := adapter.unanswered(TAKE_BACK_S)):
                why = f"{unanswered} request(s) of the ended run still unanswered"
            if why:
                print(f"ros2 adapter: not reused: {why}; a fresh node serves the next run", file=sys.stderr, flush=True)
            return why is None

        serve_runs(adapter, hello, node, ready, greet,
                   None if recorder else {True: reset, "mission": take_back}.get(mapping.lifecycle))
    finally:
        if recorder:
            time.sleep(RECORDER_DRAIN_S)  # what is still in flight to the recorder (its topics lag the replies)
            recorder.close()
        stop_all([node], grace_s=1.0)  # within the bench's grace after its SIGTERM
        if adapter:
            adapter.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m harness.sut.ros2.serve", description=__doc__.split("\n\n")[0])
    parser.add_argument("--mapping", required=True, help="the ros2.toml beside the interface")
    parser.add_argument("--startup-timeout", type=float, default=60.0)
    parser.add_argument("node", nargs="+", help="the SUT node's command, after --")
    args = parser.parse_args(argv)
    try:
        code = run_main(run, args)
    except SystemExit as e:  # SIGTERM, after the teardown
        code = e.code
    # Not the interpreter's finalisation: rclpy's C++ objects, destroyed while an executor thread
    # is still inside rcl, abort the process (std::terminate); everything is stopped already.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    main()
