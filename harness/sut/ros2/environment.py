"""The one home of the environment a ROS 2 process of the bench runs in (docs/ros2.md).

`make ros2` installs each distro into a venv of its own, `.venv-ros2-<distro>`, whose prefix is
also the ROS 2 prefix (its `lib/` and `share/`), and builds `untimely_msgs` into
`build/ros2/<distro>/install`. Sourcing a `setup.bash` is replaced by:

    with Ros2Environment(ROOT, "jazzy", slot) as ros:
        subprocess.Popen([str(ros.python), "-m", "my.node"], env=ros.env)

`Ros2Environment(root, distro, slot)`, once entered (or `open()`ed; `close()` ends it):
- `env`: os.environ plus the distro venv's `bin` first on PATH, PYTHONPATH, LD_LIBRARY_PATH and
  AMENT_PREFIX_PATH for the built package, `ROS_DISTRO`, `ROS_LOG_DIR` in a private temporary
  folder, `RMW_IMPLEMENTATION=rmw_fastrtps_cpp`, `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` (no
  packet leaves this machine; rmw_fastrtps adds the shared-memory transport, whose /dev/shm files
  a killed process leaves behind: `close()` sweeps them), the Fast DDS profile fastdds.xml (data
  sharing off, faster announcements), and a `ROS_DOMAIN_ID` no other holder on this machine has;
- `python`: the distro venv's interpreter; `domain_id`; `log_dir`; `distro`.
A user's interface packages (`untimely init --interfaces`, interfaces.py) are found before
untimely_msgs: the install prefixes `interfaces`, else those of $UNTIMELY_ROS2_INTERFACES
(os.pathsep-separated, as a target's suts.toml `env` sets it for each distro's SUT).
The domain id is held by an flock on a file of a machine-wide folder for as long as the object is
open (the kernel releases it if the process dies), and an id is not handed out while a living
process was started with it (`domain_ids_in_use`): 8 slots of a campaign and several pytest
processes, even of other checkouts, never share one. `slot` says where the search starts, so a
campaign's slots usually get the same ids run after run. `close()` removes the log folder and
the shared memory of dead Fast DDS participants (`sweep_dead_segments`).
`installed(root, distro)` says whether `make ros2` has built the distro, else why not.
"""
from __future__ import annotations

import fcntl
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

from harness.errors import Ros2Error
from harness.target.ros2_texts import INTERFACES_VARIABLE

DISTROS = ("jazzy", "kilted")
DOMAIN_SETTING = re.compile(rb"(?:^|\0)ROS_DOMAIN_ID=(\d+)\0")  # in /proc/PID/environ
DEFAULT_DISTRO = "jazzy"
# 0 is every ROS 2 user's default; above 101 Fast DDS's port formula leaves Linux's port range.
DOMAIN_IDS = range(1, 102)
LOCK_DIR = Path(tempfile.gettempdir()) / "untimely-ros2-domains"
PROFILE = Path(__file__).resolve().parent / "fastdds.xml"
# Fast DDS 2 (Jazzy) reads the first; Fast DDS 3 (Kilted) the second, and warns on the first.
PROFILE_VARIABLE = {"jazzy": "FASTRTPS_DEFAULT_PROFILES_FILE", "kilted": "FASTDDS_DEFAULT_PROFILES_FILE"}
PYTHON_DIR = f"python{sys.version_info.major}.{sys.version_info.minor}"
SHM = Path("/dev/shm")
# A participant's segment (16 hex digits) or a port of Fast DDS 2 (fastrtps_) or 3 (fastdds_).
SEGMENT = re.compile(r"(fastrtps|fastdds)_(port\d+|[0-9a-f]{16})")
# Fast DDS creates a segment's lock file and locks it in the next system call: a younger unlocked
# one may be in that gap, an older one has lost its owner.
SETTLE_S = 1.0


def venv(root: Path, distro: str) -> Path:
    return Path(root) / f".venv-ros2-{distro}"


def install_prefix(root: Path, distro: str) -> Path:
    """Where `make ros2` installs the built untimely_msgs of a distro."""
    return Path(root) / "build" / "ros2" / distro / "install"


def installed(root: Path, distro: str) -> str | None:
    """None when `make ros2` has installed the distro and built untimely_msgs, else what is missing."""
    if distro not in DISTROS:
        return f"ROS 2 distro {distro!r} is not one the bench installs; use one of {', '.join(DISTROS)}"
    for path in (venv(root, distro) / ".installed", install_prefix(root, distro) / ".built"):
        if not path.exists():
            return f"ROS 2 {distro} is not installed: {path} is missing; run `make ros2`"
    return None


class Ros2Environment:
    """The environment of one slot's ROS 2 processes on one distro (see the module's docstring)."""

    def __init__(self, root: Path, distro: str = DEFAULT_DISTRO, slot: int = 0, interfaces: tuple[Path, ...] | None = None):
        missing = installed(root, distro)
        if missing:
            raise Ros2Error(missing)
        self.root, self.distro, self.slot = Path(root), distro, slot
        if interfaces is None:
            interfaces = tuple(Path(p) for p in os.environ.get(INTERFACES_VARIABLE, "").split(os.pathsep) if p)
        self.interfaces = interfaces
        self.python = venv(root, distro) / "bin" / "python"
        self.domain_id: int | None = None
        self.log_dir: Path | None = None
        self.env: dict[str, str] = {}
        self._lock = None

    def open(self) -> Ros2Environment:
        self._lock, self.domain_id = hold_domain_id(self.slot)
        self.log_dir = Path(tempfile.mkdtemp(prefix=f"untimely-ros2-log-{self.domain_id}-"))
        self.env = self._environment()
        return self

    def close(self, settle: bool = True) -> None:
        """Gives the log folder and domain id back, and sweeps what dead processes left in /dev/shm
        (without `settle`, not waiting for files too young to tell: sweep_dead_segments)."""
        sweep_dead_segments(settle=settle)  # what its processes, killed or ended by os._exit, left
        if self.log_dir is not None:
            shutil.rmtree(self.log_dir, ignore_errors=True)
            self.log_dir = None
        if self._lock is not None:
            self._lock.close()  # closing the file releases its flock
            self._lock, self.domain_id = None, None

    def __enter__(self) -> Ros2Environment:
        return self.open()

    def __exit__(self, *exc) -> None:
        self.close()

    def _environment(self) -> dict[str, str]:
        prefix, built = venv(self.root, self.distro), [*self.interfaces, install_prefix(self.root, self.distro)]
        libs = [*(b / "lib" for b in built), prefix / "lib",
                *sorted((prefix / "lib" / PYTHON_DIR / "site-packages").glob("ros_*.libs"))]
        env = dict(os.environ)
        env.update({
            "PATH": _joined([prefix / "bin"], env.get("PATH")),
            "PYTHONPATH": _joined([*(b / "lib" / PYTHON_DIR / "site-packages" for b in built), self.root],
                                  env.get("PYTHONPATH")),
            "LD_LIBRARY_PATH": _joined(libs, env.get("LD_LIBRARY_PATH")),
            "AMENT_PREFIX_PATH": _joined([*built, prefix], None),
            "VIRTUAL_ENV": str(prefix),
            # The wheels' bootstrapper re-executes python to set LD_LIBRARY_PATH, set above already.
            "_ROS_WHEELS_BOOTSTRAP_COMPLETE": "1",
            "ROS_LOG_DIR": str(self.log_dir),
            "ROS_DOMAIN_ID": str(self.domain_id),
            "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
            "ROS_DISTRO": self.distro,
            "RMW_IMPLEMENTATION": "rmw_fastrtps_cpp",
            PROFILE_VARIABLE[self.distro]: str(PROFILE),
        })
        # A user's own settings that would undo the confinement: the deprecated localhost switch
        # (it overrides the discovery range), peers elsewhere, another profile.
        for name in ("ROS_LOCALHOST_ONLY", "ROS_STATIC_PEERS", *set(PROFILE_VARIABLE.values()) - {PROFILE_VARIABLE[self.distro]}):
            env.pop(name, None)
        return env


def _joined(first: list[Path], rest: str | None) -> str:
    return os.pathsep.join([str(p) for p in first] + ([rest] if rest else []))


def hold_domain_id(slot: int):
    """An open lock file whose flock holds a domain id (searched from `slot` on) until it is
    closed or the process ends, and the id."""
    LOCK_DIR.mkdir(mode=0o1777, exist_ok=True)
    ids, used = list(DOMAIN_IDS), domain_ids_in_use()
    start = slot % len(ids)
    for domain_id in ids[start:] + ids[:start]:
        if domain_id in used:
            continue
        lock = open(LOCK_DIR / f"{domain_id}.lock", "a")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            continue
        return lock, domain_id
    raise Ros2Error(f"all {len(ids)} ROS 2 domain ids ({ids[0]}-{ids[-1]}) are held by other runs "
                    f"on this machine (locks in {LOCK_DIR}); wait for them to end or run fewer slots")


def domain_ids_in_use(proc: Path = Path("/proc")) -> set[int]:
    """The ROS_DOMAIN_ID of every living process that was started with one. A lock is given back
    when its environment closes, which may be before the processes it started are gone (a stopped
    slot gives its id back at once, its adapter and node still tearing down): such an id is not
    handed out again while they live, or a new holder's nodes would talk to the dying ones."""
    used = set()
    for environ in proc.glob("[0-9]*/environ"):
        try:
            found = DOMAIN_SETTING.search(environ.read_bytes())
        except OSError:  # ended meanwhile, or not ours to read
            continue
        if found:
            used.add(int(found[1]))
    return used


def sweep_dead_segments(shm: Path = SHM, settle: bool = True) -> list[str]:
    """Removes the Fast DDS shared-memory files (a segment or port, its lock files, its semaphore)
    whose owner is gone, as Fast DDS's `fastdds shm clean` does, and returns their segments' names.
    A living owner holds an flock on the segment's `_el` file (a port's listeners on `_el` or
    `_sl`); a port left with no lock file at all is dead once nothing has written it for a while.
    A file younger than SETTLE_S may be one whose creator has yet to lock it: with `settle`, such
    files (of processes that just ended, as a rule) are waited for once, SETTLE_S."""
    removed, young = _sweep(shm)
    if young and settle:
        time.sleep(SETTLE_S)
        removed += _sweep(shm)[0]
    return removed


def _sweep(shm: Path) -> tuple[list[str], bool]:
    """The dead segments removed, and whether one was too young to tell."""
    removed, young = [], False
    for segment in sorted(shm.iterdir()):
        if not SEGMENT.fullmatch(segment.name):
            continue
        locks = [lock for lock in (shm / f"{segment.name}_el", shm / f"{segment.name}_sl") if lock.exists()]
        if any(_age(path) < SETTLE_S for path in locks or [segment]):
            young = True
            continue
        fds = [_unowned(lock) for lock in locks]
        try:
            if None not in fds:
                for path in (segment, *locks, shm / f"sem.{segment.name}_mutex"):
                    path.unlink(missing_ok=True)
                removed.append(segment.name)
        finally:
            for fd in fds:
                if fd is not None:
                    os.close(fd)
    return removed, young


def _age(path: Path) -> float:
    """Seconds since the file was last written (a file removed meanwhile by its owner: very old)."""
    try:
        return time.time() - path.stat().st_mtime
    except FileNotFoundError:
        return float("inf")


def _unowned(lock: Path) -> int | None:
    """An open descriptor holding the lock file's flock when no process holds it, else None."""
    try:
        fd = os.open(lock, os.O_RDONLY)
    except FileNotFoundError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    return fd
