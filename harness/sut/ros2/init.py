"""`untimely init DIR --from-ros2 'COMMAND'` (docs/ros2.md, "Targets from the ROS 2 graph"):
COMMAND runs in a ROS 2 domain of its own, confined to this machine (environment.py), on the first
installed distro; graph.py reads the graph under that distro's rclpy once it has settled;
COMMAND is stopped, and harness.target.ros2_graph derives the target that ros2_texts writes.
Without --from-ros2, `init` is harness.target.scaffold's (harness/commands/init.py chooses). With
--from-bag, the golden mission is a recorded session's (harness/campaign/from_bag.py, which reads
the bag and calls from_ros2 here). With --interfaces, the user's interface packages are built for
every installed distro first (interfaces.py), and both the graph's reading and the written SUTs
(suts.toml's env) find them.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Callable

from harness import ROOT
from harness.sut.ros2.environment import DEFAULT_DISTRO, DISTROS, Ros2Environment, installed
from harness.sut.ros2.interfaces import built, package
from harness.errors import UntimelyError
from harness.target.mission import PROPERTIES_FILE, SUTS_FILE
from harness.target.ros2_graph import Ros2Target, derive
from harness.target.ros2_texts import WRITTEN, write

SETTLE_S = 2.0  # the graph must stay unchanged this long: nodes create their servers after they appear
GRAPH_TIMEOUT_S = 60.0
STOP_GRACE_S = 5.0
POLL_S = 0.1


def read_graph(command: str, distro: str, cwd: Path, interfaces: tuple[Path, ...] = ()) -> dict:
    """The graph COMMAND brings up (graph.py's JSON), COMMAND run from `cwd` and stopped afterwards;
    `interfaces`: the install prefixes of the user's interface packages."""
    # a slot of its own (the pid spreads them): one domain per reading, even beside a campaign
    with Ros2Environment(ROOT, distro, os.getpid(), interfaces) as ros, tempfile.TemporaryFile("w+") as log:
        node = subprocess.Popen(["bash", "-c", f"exec {command}"], cwd=cwd, env=ros.env, stdin=subprocess.DEVNULL,
                                stdout=log, stderr=log, start_new_session=True)
        probe = subprocess.Popen([str(ros.python), "-m", "harness.sut.ros2.graph", "--settle", str(SETTLE_S),
                                  "--timeout", str(GRAPH_TIMEOUT_S)], env=ros.env, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
        try:
            while probe.poll() is None and node.poll() is None:
                time.sleep(POLL_S)
            exited = node.poll()
        finally:
            _stop(probe, group=False)
            _stop(node)
        out, err = probe.communicate()
        if exited is not None or probe.returncode != 0:
            log.seek(0)
            why = f"it exited with status {exited}" if exited is not None else err.strip()[-500:]
            raise UntimelyError(f"--from-ros2 {command!r}: no graph could be read on {distro}: {why}; its output: "
                                f"{log.read().strip()[-500:] or '(none)'}; check that it starts a node from {cwd}")
    return json.loads(out)


def _stop(process: subprocess.Popen, group: bool = True) -> None:
    """SIGTERM to the process (COMMAND: its process group), SIGKILL after the grace period."""
    for sig, wait in ((signal.SIGTERM, STOP_GRACE_S), (signal.SIGKILL, None)):
        try:
            os.killpg(process.pid, sig) if group else process.send_signal(sig)
        except ProcessLookupError:
            pass
        try:
            process.wait(wait)
            return
        except subprocess.TimeoutExpired:
            continue


def from_ros2(folder: Path, command: str, recorded: Callable[[Path, Ros2Target], str] | None = None,
              interfaces: tuple[str, ...] = ()) -> int:
    """`init FOLDER --from-ros2 COMMAND [--interfaces PKG_DIR ...]`; `recorded(draft, target)`: the
    golden mission's text, given the target written to the folder `draft`."""
    distros = [d for d in DISTROS if installed(ROOT, d) is None]
    if not distros:
        raise UntimelyError(f"--from-ros2 needs ROS 2: {installed(ROOT, DEFAULT_DISTRO)}")
    packages = [package(p) for p in interfaces]  # all refused or none, before any build
    prefixes = {d: built(ROOT, d, packages) for d in distros}
    cwd = Path.cwd()
    target = derive(command, read_graph(command, distros[0], cwd, prefixes[distros[0]]))
    golden = None
    if recorded is not None:
        with tempfile.TemporaryDirectory(prefix="untimely-init-") as draft:
            write(Path(draft) / "target", target, prefixes, cwd)
            golden = recorded(Path(draft) / "target", target)
    write(folder, target, prefixes, cwd, golden)
    print(f"wrote the target {folder}/ from the ROS 2 graph of {command!r} (read on {distros[0]}): "
          f"{', '.join(WRITTEN)}")
    print(f"  {len(target.services)} services in {len(target.nodes)} node(s), {len(target.properties)} properties; "
          f"SUTs: {', '.join(d for d in distros)}")
    for note in target.notes:
        print(f"  not derived: {note}")
    campaign = (f"untimely campaign --mission {folder} --strategy focused --budget 10m --shrink --sut "
                + ",".join(f"{line.strip('[]')}" for line in (folder / SUTS_FILE).read_text().splitlines()
                           if line.startswith("[")))
    if not target.properties:  # a campaign judges properties: it would refuse to start
        print(f"next: write at least one [[property]] in {folder / PROPERTIES_FILE} (none could be derived), "
              f"then: {campaign}")
    else:
        print(f"next: {campaign}")
    return 0
