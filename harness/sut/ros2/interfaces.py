"""A user's ROS 2 interface packages (`untimely init DIR --from-ros2 COMMAND --interfaces PKG_DIR`):
each built against every installed distro as untimely_msgs is (build.py, under the distro's venv),
cached by content, and found by every ROS 2 process of the target (environment.py).

A package is a folder with package.xml and action/, srv/ or msg/. Its build goes to
`build/ros2/<distro>/interfaces/<name>-<digest>/` (install/, build.log), the digest a SHA-256 of its
files' paths and bytes: an unchanged package is built once per distro, an edited one afresh. The
packages build in the order given, each finding those before it (a package using another's
messages comes after it). A package that fails to build is refused with the end of its log.
"""
from __future__ import annotations

import hashlib
import subprocess
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path

from harness.errors import UntimelyError
from harness.sut.ros2.build import BUILT, log_tail
from harness.sut.ros2.environment import install_prefix, venv

KINDS = ("action", "srv", "msg")
DIGEST_CHARS = 16


@dataclass(frozen=True)
class Package:
    folder: Path
    name: str
    digest: str

    def out(self, root: Path, distro: str) -> Path:
        return install_prefix(root, distro).parent / "interfaces" / f"{self.name}-{self.digest}"


def package(folder: str | Path) -> Package:
    """The package in `folder`, refused unless it has package.xml naming it and interface files."""
    folder = Path(folder).resolve()
    where = f"--interfaces {folder}"
    try:
        name = ElementTree.parse(folder / "package.xml").getroot().findtext("name")
    except (OSError, ElementTree.ParseError) as e:
        raise UntimelyError(f"{where}: no readable package.xml ({e}); give the folder of a ROS 2 interface "
                            "package (package.xml, and action/, srv/ or msg/)") from None
    if not name or not name.strip():
        raise UntimelyError(f"{where}: its package.xml has no <name>; add one")
    if not any(path for kind in KINDS for path in (folder / kind).glob(f"*.{kind}")):
        raise UntimelyError(f"{where}: no .action, .srv or .msg file in action/, srv/ or msg/; give the folder of "
                            "an interface package")
    digest = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        digest.update(str(path.relative_to(folder)).encode() + b"\0" + path.read_bytes() + b"\0")
    return Package(folder, name.strip(), digest.hexdigest()[:DIGEST_CHARS])


def built(root: Path, distro: str, packages: list[Package]) -> tuple[Path, ...]:
    """The install prefixes of `packages` on `distro`, building those not yet in the cache."""
    prefixes: list[Path] = []
    for pkg in packages:
        out = pkg.out(root, distro)
        if not (out / "install" / BUILT).exists():
            print(f"building {pkg.name} for ROS 2 {distro} (once: cached in {out})", flush=True)
            out.mkdir(parents=True, exist_ok=True)
            argv = [str(venv(root, distro) / "bin" / "python"), "-m", "harness.sut.ros2.build", distro,
                    "--package", str(pkg.folder), "--out", str(out), *(f"--depends={p}" for p in prefixes)]
            done = subprocess.run(argv, cwd=root, capture_output=True, text=True)
            if done.returncode != 0:
                raise UntimelyError(f"--interfaces {pkg.folder}: building {pkg.name} for ROS 2 {distro} failed; "
                                    f"the end of its log ({out / 'build.log'}):\n{log_tail(out)}\n"
                                    f"{done.stderr.strip().splitlines()[-1] if done.stderr.strip() else ''}")
        prefixes.append(out / "install")
    return tuple(prefixes)
