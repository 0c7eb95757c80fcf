"""The one home of the environment a ROS 2 process of the bench runs in (docs/ros2.md).

`make ros2` installs each distro into a venv of its own, `.venv-ros2-<distro>`, whose prefix is
also the ROS 2 prefix (its `lib/` and `share/`), and builds `untimely_msgs` into
`build/ros2/<distro>/install`. Sourcing a `setup.bash` is replaced by:

    with Ros2Environment(ROOT, "jazzy", slot) as ros:
        subprocess.Popen([str(ros.python), "-m", "my.node"], env=ros.env)

`Ros2Environment(root, distro, slot)`, once entered (or `open()`ed; `close()` ends it):
- `env`: os.environ plus the distro venv's `bin` first on PATH, PYTHONPATH, LD_LIBRARY_PATH and
  AMENT_PREFIX_PATH for the built package, `ROS_DISTRO`, `ROS_LOG_DIR` in a private temporary
  folder, `RMW_IMPLEMENTATION=rmw_fastrtps_cpp`, the Fast DDS profile fastdds.xml that keeps every
  packet on loopback (UDP on 127.0.0.1, no shared memory) and announces faster, and a
  `ROS_DOMAIN_ID` that no other holder on this machine has. The discovery range is SUBNET: on
  Jazzy, LOCALHOST makes rmw_fastrtps replace the profile's transports with its own, shared
  memory included, whose /dev/shm segments a killed process leaves behind; the profile confines;
- `python`: the distro venv's interpreter; `domain_id`; `log_dir`; `distro`.
The domain id is held by an flock on a file of a machine-wide folder for as long as the object is
open (the kernel releases it if the process dies): 8 slots of a campaign and several pytest
processes, even of other checkouts, never share one. `slot` says where the search starts, so a
campaign's slots usually get the same ids run after run. `close()` removes the log folder.
`installed(root, distro)` says whether `make ros2` has built the distro, else why not.
"""
from __future__ import annotations

import fcntl
import os
import shutil
import sys
import tempfile
from pathlib import Path

from harness.errors import UntimelyError

DISTROS = ("jazzy", "kilted")
DEFAULT_DISTRO = "jazzy"
# 0 is every ROS 2 user's default; above 101 Fast DDS's port formula leaves Linux's port range.
DOMAIN_IDS = range(1, 102)
LOCK_DIR = Path(tempfile.gettempdir()) / "untimely-ros2-domains"
PROFILE = Path(__file__).resolve().parent / "fastdds.xml"
# Fast DDS 2 (Jazzy) reads the first; Fast DDS 3 (Kilted) the second, and warns on the first.
PROFILE_VARIABLE = {"jazzy": "FASTRTPS_DEFAULT_PROFILES_FILE", "kilted": "FASTDDS_DEFAULT_PROFILES_FILE"}
PYTHON_DIR = f"python{sys.version_info.major}.{sys.version_info.minor}"


class Ros2Error(UntimelyError):
    """ROS 2 is missing for a distro, or no domain id is free."""


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

    def __init__(self, root: Path, distro: str = DEFAULT_DISTRO, slot: int = 0):
        missing = installed(root, distro)
        if missing:
            raise Ros2Error(missing)
        self.root, self.distro, self.slot = Path(root), distro, slot
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

    def close(self) -> None:
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
        prefix, built = venv(self.root, self.distro), install_prefix(self.root, self.distro)
        libs = [built / "lib", prefix / "lib", *sorted((prefix / "lib" / PYTHON_DIR / "site-packages").glob("ros_*.libs"))]
        env = dict(os.environ)
        env.update({
            "PATH": _joined([prefix / "bin"], env.get("PATH")),
            "PYTHONPATH": _joined([built / "lib" / PYTHON_DIR / "site-packages", self.root], env.get("PYTHONPATH")),
            "LD_LIBRARY_PATH": _joined(libs, env.get("LD_LIBRARY_PATH")),
            "AMENT_PREFIX_PATH": _joined([built, prefix], None),
            "VIRTUAL_ENV": str(prefix),
            # The wheels' bootstrapper re-executes python to set LD_LIBRARY_PATH, set above already.
            "_ROS_WHEELS_BOOTSTRAP_COMPLETE": "1",
            "ROS_LOG_DIR": str(self.log_dir),
            "ROS_DOMAIN_ID": str(self.domain_id),
            "ROS_AUTOMATIC_DISCOVERY_RANGE": "SUBNET",
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
    ids = list(DOMAIN_IDS)
    start = slot % len(ids)
    for domain_id in ids[start:] + ids[:start]:
        lock = open(LOCK_DIR / f"{domain_id}.lock", "a")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            continue
        return lock, domain_id
    raise Ros2Error(f"all {len(ids)} ROS 2 domain ids ({ids[0]}-{ids[-1]}) are held by other runs "
                    f"on this machine (locks in {LOCK_DIR}); wait for them to end or run fewer slots")
