"""The layout (docs/architecture.md): a target's file names have one home, harness/target/mission.py,
and no other Python file of harness/ spells them out (but those left, below); no module path from before
harness/sut/ is left in the repository, yet a command or a layer.toml written with one still runs."""
import ast
import shutil
import subprocess
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, MOVED_MODULES, ROOT, current_modules
from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.target import mission
from harness.target.mission import load_layer
from harness.target.script import parse

TARGET = ROOT / "harness" / "target"
HOME = TARGET / "mission.py"
# The one literal left in harness/target/: the adapter skeleton init copies into a user's target,
# which runs without the bench and so spells its file's name.
LEFT = frozenset({"harness/target/skeleton/adapter.py:40: 'interface.toml'"})
FILE_NAMES = frozenset(value for name, value in vars(mission).items() if name.endswith("_FILE"))


def _names_a_target_file(text: str) -> bool:
    """Whether a string literal is a target file's name, alone or as a path's last part (a message
    that ends with one, e.g. "such as missions/dala/golden.mission", is prose)."""
    return text in FILE_NAMES or (" " not in text and any(text.endswith("/" + name) for name in FILE_NAMES))


def file_names_outside_their_home(folder: Path) -> list[str]:
    found = []
    for path in sorted(folder.rglob("*.py")):
        if path == HOME:
            continue  # the names' home
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and _names_a_target_file(node.value):
                found.append(f"{path.relative_to(folder.parent)}:{node.lineno}: {node.value!r}")
    return found


def test_the_target_owns_its_file_names():
    assert {"interface.toml", "properties.toml", "golden.mission", "layer.toml", "world.toml", "suts.toml",
            "ros.toml", "ros2.toml"} <= FILE_NAMES
    found = file_names_outside_their_home(ROOT / "harness")
    assert [f for f in found if f not in LEFT] == [], "import the name from harness/target/mission.py"
    assert not LEFT - set(found), "a literal left is gone: take it out of LEFT"


def test_the_check_finds_a_file_name_where_there_is_one(tmp_path):
    module = tmp_path / "harness" / "analysis" / "sneaky.py"
    module.parent.mkdir(parents=True)
    module.write_text('"""Reads interface.toml (a docstring is prose)."""\n'
                      'def f(folder):\n    return folder / "interface.toml", f"{folder}/golden.mission"\n')
    assert file_names_outside_their_home(tmp_path / "harness") == [
        "harness/analysis/sneaky.py:3: 'interface.toml'", "harness/analysis/sneaky.py:3: '/golden.mission'"]


def test_no_module_path_from_before_harness_sut_is_left():
    """Only MOVED_MODULES, which maps them, the paragraph of docs/architecture.md that says they still
    run, and this test name them."""
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True, check=True)
    old = [name.replace(".", "/") for name in MOVED_MODULES] + list(MOVED_MODULES) + [
        "harness/dispatch/external", "harness.dispatch.external", "harness.dispatch.executive", "harness.dispatch.processes",
        "harness/store/bags", "harness.store.bags"]
    left = []
    for relative in filter(None, listed.stdout.split("\0")):
        path = ROOT / relative
        if relative in ("harness/__init__.py", "tests/project/test_layout.py") or not path.is_file():
            continue
        text = path.read_text(errors="replace")
        if relative == "docs/architecture.md":
            text = "\n\n".join(p for p in text.split("\n\n") if "MOVED_MODULES" not in p)
        left += [f"{relative}: {name}" for name in old if _names_module(text, name)]
    assert left == []


def _names_module(text: str, name: str) -> bool:
    """`name` in `text` as a whole module or folder name (harness.sim, not harness.simulated)."""
    start = text.find(name)
    while start != -1:
        after = text[start + len(name):start + len(name) + 1]
        if not (after.isalnum() or after == "_"):
            return True
        start = text.find(name, start + 1)
    return False


@pytest.mark.parametrize("old, new", [
    ("{python} -m harness.adapters.sim --variant genom", "{python} -m harness.sut.simulated --variant genom"),
    ("python -m harness.adapters.ros2 --mapping m -- python -m harness.adapters.ros2.dala_node",
     "python -m harness.sut.ros2 --mapping m -- python -m harness.sut.ros2.dala_node"),
    ("harness.adapters.ros.dala_node", "harness.sut.ros.dala_node"),
    ("harness.sim.dala.behaviour", "harness.sut.dala.behaviour"),
    ("harness.sim.kernel", "harness.sut.simulated.kernel"),
    *((unmoved, unmoved) for unmoved in ("harness.simulated", "harness.adapters.ross", "my.harness.sim", "harness.sim_x")),
])
def test_a_moved_module_is_named_by_its_current_name(old, new):
    assert current_modules(old) == new


def test_a_command_recorded_before_the_move_still_runs(interface):
    """A store's campaigns.config (and an older suts.toml) may hold `-m harness.adapters.sim`."""
    sut = ExternalSut("sim", command=f"{{python}} -m harness.adapters.sim --variant reference --mission "
                                     f"{DEFAULT_MISSION_DIR}", time_scale=20.0)
    assert "harness.sut.simulated" in sut.argv()
    trace = run_external(parse("send rflex.Init as ri\nwait ri\n", "short"), sut, 7, interface)
    assert trace.outcome == "completed", trace.error
    assert [e[2] for e in trace.events] == ["request", "final"]


def test_a_layer_toml_written_before_the_move_still_builds(tmp_path):
    for name in ("layer.toml", "world.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, tmp_path / name)
    path = tmp_path / "layer.toml"
    path.write_text(path.read_text().replace('"harness.sut.dala.behaviour"', '"harness.sim.dala.behaviour"'))
    assert 'behaviour = "harness.sim.dala.behaviour"' in path.read_text()
    assert callable(load_layer(tmp_path).behaviour_module().build)
