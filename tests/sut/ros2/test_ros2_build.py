"""`make ros2`'s build of untimely_msgs (harness/sut/ros2/build.py): the wheels' CMake files
get this machine's include folders, once; every interface file of the package is built for each
distro, and the build's seconds are recorded."""
import subprocess
import sysconfig

import numpy
import pytest

from harness import ROOT
from harness.sut.ros2.build import SOURCE, fix_cmake_paths
from harness.sut.ros2.environment import DISTROS, Ros2Environment, install_prefix, installed, venv

EXPORTED = ('set_target_properties(Python3::Module PROPERTIES\n  INTERFACE_INCLUDE_DIRECTORIES '
            '"/opt/python/cp311-cp311/include/python3.11;/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include"\n)\n')


def test_the_build_machines_include_folders_become_this_ones_once(tmp_path):
    cmake = tmp_path / "share" / "std_msgs" / "cmake" / "export_std_msgs__rosidl_generator_pyExport.cmake"
    other = tmp_path / "share" / "std_msgs" / "cmake" / "std_msgsConfig.cmake"
    cmake.parent.mkdir(parents=True)
    cmake.write_text(EXPORTED)
    other.write_text("# nothing of the build machine\n")
    assert fix_cmake_paths(tmp_path) == [cmake]
    assert cmake.read_text() == EXPORTED.replace("/opt/python/cp311-cp311/include/python3.11", sysconfig.get_paths()["include"]) \
        .replace("/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include", numpy.get_include())
    assert fix_cmake_paths(tmp_path) == [] and other.read_text() == "# nothing of the build machine\n"


@pytest.mark.slow
@pytest.mark.parametrize("distro", DISTROS)
def test_every_interface_file_is_built_and_the_wheels_name_no_foreign_path(distro):
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    foreign = [str(p) for p in (venv(ROOT, distro) / "share").glob("*/cmake/*.cmake") if "/opt/python/" in p.read_text()]
    assert not foreign, foreign
    assert float((install_prefix(ROOT, distro).parent / "build-seconds").read_text()) > 0
    interfaces = sorted(f"{p.parent.name} {p.stem}" for p in SOURCE.glob("*/*") if p.suffix in (".action", ".srv", ".msg"))
    assert "action Request" in interfaces and "srv Call" in interfaces
    imports = "; ".join(f"from untimely_msgs.{kind} import {name}" for kind, name in (i.split() for i in interfaces))
    with Ros2Environment(ROOT, distro, slot=0) as ros:
        done = subprocess.run([str(ros.python), "-c", imports], env=ros.env, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
