"""Builds a ROS 2 interface package against one distro's wheels, run under that distro's venv:
`python -m harness.sut.ros2.build jazzy` builds the bench's own `untimely_msgs` (`make ros2`);
`python -m harness.sut.ros2.build jazzy --package DIR --out OUT` builds a user's package (a folder
with package.xml and action/, srv/, msg/), as `untimely init --interfaces` does (interfaces.py).

The wheels' exported CMake files name the Python headers and NumPy of the machine that built them
(`/opt/python/cp311-cp311/...`): `fix_cmake_paths` rewrites them to this venv's, once (a second
call finds nothing to rewrite). Then CMake (its PyPI wheel) and Ninja build every `.action`,
`.srv` and `.msg` file of the package into `OUT/install` (untimely_msgs: `build/ros2/<distro>`);
the seconds it took go to `OUT/build-seconds`, CMake's output to `OUT/build.log`, and
`install/.built` marks it done. A build starts clean (its own build/ and install/ removed, nothing
else of OUT), so no stale interface survives.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

from harness.sut.ros2.environment import DISTROS, PYTHON_DIR, install_prefix, venv

SOURCE = Path(__file__).resolve().parent / "untimely_msgs"
BUILT = ".built"  # in the install folder: written last
LOG_TAIL = 40  # lines of CMake's output shown when a build fails
# The build machine's Python headers and NumPy headers, under its interpreter's prefix as the
# manylinux images name it (cp311-cp311, cp312-cp312...).
FOREIGN = re.compile(r"/opt/python/cp\d+-cp\d+t?/(include/python[\d.]+t?|lib/python[\d.]+t?/site-packages/numpy/_core/include)")


def fix_cmake_paths(prefix: Path) -> list[Path]:
    """Rewrites the build machine's Python and NumPy include folders in the wheels' CMake files."""
    import numpy  # the distro venv's, whose headers the build uses

    local = {"include": sysconfig.get_paths()["include"], "numpy": numpy.get_include()}
    fixed = []
    for path in sorted((prefix / "share").glob("*/cmake/*.cmake")):
        text = path.read_text()
        new = FOREIGN.sub(lambda m: local["numpy" if "numpy" in m.group(1) else "include"], text)
        if new != text:
            path.write_text(new)
            fixed.append(path)
    return fixed


def build_package(root: Path, distro: str, source: Path, out: Path, depends: tuple[Path, ...] = ()) -> float:
    """Builds and installs the package `source` for `distro` into `out`/install, finding the
    install prefixes `depends` (packages it uses); returns the seconds it took."""
    prefix, install, work = venv(root, distro), out / "install", out / "build"
    for stale in (install, work):
        shutil.rmtree(stale, ignore_errors=True)
    fix_cmake_paths(prefix)
    found = os.pathsep.join(str(p) for p in (*depends, prefix))
    env = dict(os.environ, PATH=f"{prefix / 'bin'}{os.pathsep}{os.environ['PATH']}",
               AMENT_PREFIX_PATH=found, CMAKE_PREFIX_PATH=found,
               LD_LIBRARY_PATH=os.pathsep.join([*(str(p / "lib") for p in (*depends, prefix)),
                                                 os.environ.get("LD_LIBRARY_PATH", "")]))
    env.pop("ROS_DISTRO", None)
    started = time.monotonic()
    work.mkdir(parents=True)
    with open(out / "build.log", "w") as log:  # CMake's hundreds of lines; shown on failure
        for argv in (["cmake", "-S", str(source), "-B", str(work), "-G", "Ninja", "-DBUILD_TESTING=OFF",
                      f"-DCMAKE_INSTALL_PREFIX={install}", f"-DPython3_EXECUTABLE={sys.executable}",
                      "-DCMAKE_BUILD_TYPE=Release"],
                     ["cmake", "--build", str(work)], ["cmake", "--install", str(work)]):
            subprocess.run(argv, env=env, check=True, stdout=log, stderr=subprocess.STDOUT)
    seconds = time.monotonic() - started
    (out / "build-seconds").write_text(f"{seconds:.1f}\n")
    (install / BUILT).write_text(f"{source.name} for ROS 2 {distro}, {PYTHON_DIR}\n")
    return seconds


def log_tail(out: Path) -> str:
    """The end of a build's log (what a failed build is refused with)."""
    log = out / "build.log"
    lines = log.read_text(errors="replace").splitlines() if log.exists() else ["(no build log)"]
    return "\n".join(lines[-LOG_TAIL:])


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python -m harness.sut.ros2.build", description=__doc__.split("\n\n")[0])
    parser.add_argument("distro", choices=DISTROS)
    parser.add_argument("--package", type=Path, help="a package folder to build (default: untimely_msgs)")
    parser.add_argument("--out", type=Path, help="with --package: the folder its build and install go to")
    parser.add_argument("--depends", type=Path, action="append", default=[], help="an install prefix it uses")
    args = parser.parse_args(argv[1:])
    if (args.package is None) != (args.out is None):
        parser.error("give --package and --out together")
    source, out = (args.package, args.out) if args.package else (SOURCE, install_prefix(Path.cwd(), args.distro).parent)
    try:
        seconds = build_package(Path.cwd(), args.distro, source.resolve(), out.resolve(), tuple(args.depends))
    except subprocess.CalledProcessError as failed:
        print(log_tail(out), file=sys.stderr)
        print(f"building {source.name} for ROS 2 {args.distro} failed: `{' '.join(failed.cmd)}` exited with "
              f"{failed.returncode}; its output is in {out / 'build.log'} (the end above)", file=sys.stderr)
        return 1
    print(f"{source.name} built for ROS 2 {args.distro} in {seconds:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
