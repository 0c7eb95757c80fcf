"""Builds the interface package `untimely_msgs` against one distro's wheels (`make ros2` runs it
under that distro's venv: `python -m harness.sut.ros2.build jazzy`).

The wheels' exported CMake files name the Python headers and NumPy of the machine that built them
(`/opt/python/cp311-cp311/...`): `fix_cmake_paths` rewrites them to this venv's, once (a second
call finds nothing to rewrite). Then CMake (its PyPI wheel) and Ninja build every `.action`,
`.srv` and `.msg` file of `untimely_msgs/` into `build/ros2/<distro>/install`; the seconds it took
go to `build/ros2/<distro>/build-seconds`, CMake's output to `build.log` beside it, and
`install/.built` marks it done.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

import numpy

from harness.sut.ros2.environment import DISTROS, PYTHON_DIR, install_prefix, venv

SOURCE = Path(__file__).resolve().parent / "untimely_msgs"
# The build machine's Python headers and NumPy headers, under its interpreter's prefix as the
# manylinux images name it (cp311-cp311, cp312-cp312...).
FOREIGN = re.compile(r"/opt/python/cp\d+-cp\d+t?/(include/python[\d.]+t?|lib/python[\d.]+t?/site-packages/numpy/_core/include)")


def fix_cmake_paths(prefix: Path) -> list[Path]:
    """Rewrites the build machine's Python and NumPy include folders in the wheels' CMake files."""
    local = {"include": sysconfig.get_paths()["include"], "numpy": numpy.get_include()}
    fixed = []
    for path in sorted((prefix / "share").glob("*/cmake/*.cmake")):
        text = path.read_text()
        new = FOREIGN.sub(lambda m: local["numpy" if "numpy" in m.group(1) else "include"], text)
        if new != text:
            path.write_text(new)
            fixed.append(path)
    return fixed


def build(root: Path, distro: str) -> float:
    """Builds and installs untimely_msgs for `distro`; returns the seconds it took."""
    prefix, install = venv(root, distro), install_prefix(root, distro)
    work = install.parent / "build"
    shutil.rmtree(install.parent, ignore_errors=True)  # a clean build: no stale interface survives
    fix_cmake_paths(prefix)
    env = dict(os.environ, PATH=f"{prefix / 'bin'}{os.pathsep}{os.environ['PATH']}",
               AMENT_PREFIX_PATH=str(prefix), CMAKE_PREFIX_PATH=str(prefix),
               LD_LIBRARY_PATH=f"{prefix / 'lib'}{os.pathsep}{os.environ.get('LD_LIBRARY_PATH', '')}")
    env.pop("ROS_DISTRO", None)
    started = time.monotonic()
    work.mkdir(parents=True)
    with open(install.parent / "build.log", "w") as log:  # CMake's hundreds of lines; shown on failure
        for argv in (["cmake", "-S", str(SOURCE), "-B", str(work), "-G", "Ninja", "-DBUILD_TESTING=OFF",
                      f"-DCMAKE_INSTALL_PREFIX={install}", f"-DPython3_EXECUTABLE={sys.executable}",
                      "-DCMAKE_BUILD_TYPE=Release"],
                     ["cmake", "--build", str(work)], ["cmake", "--install", str(work)]):
            subprocess.run(argv, env=env, check=True, stdout=log, stderr=subprocess.STDOUT)
    seconds = time.monotonic() - started
    (install.parent / "build-seconds").write_text(f"{seconds:.1f}\n")
    (install / ".built").write_text(f"untimely_msgs for ROS 2 {distro}, {PYTHON_DIR}\n")
    return seconds


def main(argv: list[str]) -> int:
    if len(argv) != 2 or argv[1] not in DISTROS:
        print(f"usage: python -m harness.sut.ros2.build {{{','.join(DISTROS)}}}", file=sys.stderr)
        return 2
    try:
        seconds = build(Path.cwd(), argv[1])
    except subprocess.CalledProcessError as failed:
        log = install_prefix(Path.cwd(), argv[1]).parent / "build.log"
        print("\n".join(log.read_text().splitlines()[-40:]), file=sys.stderr)
        print(f"building untimely_msgs for ROS 2 {argv[1]} failed: `{' '.join(failed.cmd)}` exited with "
              f"{failed.returncode}; its output is in {log} (the end above)", file=sys.stderr)
        return 1
    print(f"untimely_msgs built for ROS 2 {argv[1]} in {seconds:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
