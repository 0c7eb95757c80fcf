"""One run (or, with a lifecycle node, run after run) of a ROS 2 SUT on stdio.

    python -m harness.sut.ros2 [--distro jazzy|kilted] --mapping missions/dala/ros2.toml -- NODE COMMAND ...

Runs under any Python with the bench installed (no ROS import here): it takes a ROS 2 environment
for the slot ($UNTIMELY_SLOT; environment.py: the distro's venv first on PATH, the built
untimely_msgs, a private log folder, loopback-only discovery, a domain id no other process on the
machine holds), and runs the adapter (serve.py) under the distro's interpreter in it, on this
process's stdin and stdout; the adapter starts NODE in the same environment, so `python` in NODE
is the distro's. The distro is --distro, else $UNTIMELY_ROS2_DISTRO, else jazzy. The environment
(domain id, log folder) is given back when the adapter ends; the adapter dies with this process.
"""
from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys

from harness import ROOT
from harness.sut.processes import dying_with_parent
from harness.sut.ros2.environment import DEFAULT_DISTRO, DISTROS, Ros2Environment
from harness.errors import UntimelyError
from harness.sut.protocol import encode


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m harness.sut.ros2", description=__doc__.split("\n\n")[0])
    parser.add_argument("--distro", choices=DISTROS, default=os.environ.get("UNTIMELY_ROS2_DISTRO") or DEFAULT_DISTRO,
                        help="the ROS 2 distro (default: $UNTIMELY_ROS2_DISTRO, else jazzy)")
    parser.add_argument("--mapping", required=True, help="the ros2.toml beside the interface")
    parser.add_argument("--startup-timeout", type=float, default=60.0,
                        help="seconds for the node and every server to come up (default 60)")
    parser.add_argument("node", nargs="+", help="the SUT node's command, after --")
    args = parser.parse_args(argv)
    try:
        ros = Ros2Environment(ROOT, args.distro, int(os.environ.get("UNTIMELY_SLOT", "0"))).open()
    except UntimelyError as e:
        sys.stdout.write(encode(op="error", message=str(e)))
        return 2
    try:
        adapter = subprocess.Popen(
            [str(ros.python), "-m", "harness.sut.ros2.serve", "--mapping", args.mapping,
             "--startup-timeout", str(args.startup_timeout), "--", *args.node],
            env={**ros.env, "UNTIMELY_ROS2_DISTRO": args.distro}, preexec_fn=dying_with_parent(signal.SIGTERM))
        signal.signal(signal.SIGTERM, lambda *_: stop(adapter, ros))
        return adapter.wait()
    finally:
        ros.close()


def stop(adapter: subprocess.Popen, ros: Ros2Environment) -> None:
    """SIGTERM: the adapter tears down, and the log folder and domain id are given back at once,
    as the bench's SIGKILL follows within seconds (a dying node may still write a log line, into a
    removed folder: nothing is left behind). Not waiting for the adapter keeps a hung slot's
    restart quick (so does not waiting for young files); the shared memory of its processes, if they are killed, is swept by the next
    environment closed on this machine (environment.sweep_dead_segments)."""
    adapter.terminate()
    ros.close(settle=False)


if __name__ == "__main__":
    sys.exit(main())
