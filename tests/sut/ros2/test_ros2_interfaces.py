"""A user's own interface packages (harness/sut/ros2/interfaces.py, build.py): refused when they are
no package; built for each distro once (cached by content); found by `init --from-ros2`'s reading
of the graph and by the SUTs it writes (suts.toml's env); a package that fails to build refused
with the end of its log. The builds take minutes: those tests are slow, and few."""
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from harness import ROOT
from harness.errors import UntimelyError
from harness.sut.ros2.environment import DISTROS, Ros2Environment, installed
from harness.sut.ros2.interfaces import built, package
from harness.target.interface import load_interface

HERE = Path(__file__).resolve().parent / "interfaces"
DEMO, BROKEN = HERE / "demo_interfaces", HERE / "broken_interfaces"
IMPORTS = "from demo_interfaces.action import Fib; from demo_interfaces.srv import Toggle; print(Fib.Goal().order)"


def needs(distro):
    return pytest.mark.skipif(bool(installed(ROOT, distro)), reason=str(installed(ROOT, distro)))


def test_a_folder_that_is_no_interface_package_is_refused(tmp_path):
    with pytest.raises(UntimelyError, match="no readable package.xml .*give the folder of a ROS 2 interface package"):
        package(tmp_path)
    shutil.copytree(DEMO, tmp_path / "p", ignore=shutil.ignore_patterns("action", "srv"))
    with pytest.raises(UntimelyError, match=r"p: no \.action, \.srv or \.msg file in action/, srv/ or msg/"):
        package(tmp_path / "p")
    (tmp_path / "p" / "package.xml").write_text("<package><name> </name></package>")
    with pytest.raises(UntimelyError, match="its package.xml has no <name>; add one"):
        package(tmp_path / "p")


def test_the_cache_key_is_the_packages_content(tmp_path):
    copy = shutil.copytree(DEMO, tmp_path / "demo_interfaces")
    first = package(copy)
    assert (first.name, first.digest) == ("demo_interfaces", package(DEMO).digest)  # not its place
    (copy / "srv" / "Toggle.srv").write_text((copy / "srv" / "Toggle.srv").read_text() + "# edited\n")
    edited = package(copy)
    assert edited.digest != first.digest
    assert edited.out(ROOT, "jazzy") == ROOT / "build" / "ros2" / "jazzy" / "interfaces" / f"demo_interfaces-{edited.digest}"


@pytest.mark.slow
@pytest.mark.parametrize("distro", [pytest.param(d, marks=needs(d)) for d in DISTROS])
def test_a_package_is_built_once_per_distro_and_imported_in_the_suts_environment(distro, monkeypatch, capsys):
    demo = package(DEMO)
    prefixes = built(ROOT, distro, [demo])
    assert prefixes == (demo.out(ROOT, distro) / "install",)
    stamp = (prefixes[0] / ".built").stat().st_mtime
    capsys.readouterr()
    assert built(ROOT, distro, [demo]) == prefixes and "building" not in capsys.readouterr().out  # cached
    assert (prefixes[0] / ".built").stat().st_mtime == stamp
    monkeypatch.setenv("UNTIMELY_ROS2_INTERFACES", str(prefixes[0]))  # as a written suts.toml's env sets it
    with Ros2Environment(ROOT, distro, slot=0) as ros:
        done = subprocess.run([str(ros.python), "-c", IMPORTS], env=ros.env, capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stdout.strip()) == (0, "0"), done.stderr


@pytest.mark.slow
@needs("jazzy")
def test_a_package_that_fails_to_build_is_refused_with_the_end_of_its_log(tmp_path):
    with pytest.raises(UntimelyError) as refused:
        built(ROOT, "jazzy", [package(shutil.copytree(BROKEN, tmp_path / "broken_interfaces"))])
    for words in ("--interfaces", "building broken_interfaces for ROS 2 jazzy failed; the end of its log",
                  "build.log", "no_such_package"):
        assert words in str(refused.value)


@pytest.mark.slow
@needs("jazzy")
def test_init_reads_a_node_of_its_own_interfaces_and_writes_suts_that_find_them(tmp_path):
    folder = tmp_path / "demo"
    done = subprocess.run([sys.executable, "-m", "harness", "init", str(folder), "--from-ros2",
                           f"python3 {HERE / 'demo_node.py'}", "--interfaces", str(DEMO)],
                          cwd=ROOT, capture_output=True, text=True, timeout=1200)
    assert done.returncode == 0, done.stderr[-3000:]
    # a plain node: the ROS 2 model's properties of its action and service, none of the lifecycle's
    families = {p["family"] for p in tomllib.loads((folder / "properties.toml").read_text())["property"]}
    assert {"RSP", "CAN", "GOAL"} <= families and not families & {"ACTIVE_GOALS", "TRANSITION"}, families
    assert "--strategy focused" in done.stdout, done.stdout
    interface = load_interface(folder / "interface.toml")
    assert {n: s.kind for n, s in interface.services.items()} == {
        "demo.fib": "exec", "demo.fib_cancel": "control", "demo.toggle": "control"}
    assert list(interface.services["demo.fib"].args) == ["order"]  # the goal's type was imported
    suts = tomllib.loads((folder / "suts.toml").read_text())
    for distro in [d for d in DISTROS if not installed(ROOT, d)]:
        env = suts[f"demo-{distro}"]["env"]
        assert env == {"UNTIMELY_ROS2_INTERFACES": str(package(DEMO).out(ROOT, distro) / "install")}
