"""The suite's own rules (docs/contributing.md): no test module imports another (what tests share
lives in tests/support/ or in a conftest fixture), and the fast suite (`make test-fast`, `-m "not
slow"`) still imports every package of harness/, so a change anywhere has a test that runs in minutes."""
import ast
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import counts
from tests.support.paths import ROOT, TESTS


def module_names(tests: Path) -> set[str]:
    """The names a test module can be imported by: its file's stem (pytest puts its folder on the path
    when the folder is no package) and its dotted name from the repository root."""
    names = set()
    for path in tests.rglob("test_*.py"):
        names.add(path.stem)
        names.add(".".join(path.relative_to(tests.parent).with_suffix("").parts))
    return names


def imports_of_tests(path: Path, tests: set[str]) -> list[str]:
    """`file:line: module` for each import in `path` that names a test module."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            named = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            named = [base] + [f"{base}.{alias.name}".lstrip(".") for alias in node.names]
            if node.level:  # a relative import: a test module beside this one, or in a folder above it
                named += [alias.name for alias in node.names] + [base.split(".")[-1]]
        else:
            continue
        hits = sorted({name for name in named if name in tests or name.split(".")[-1] in tests})
        found += [f"{path}:{node.lineno}: {', '.join(hits)}"] if hits else []
    return found


def violations(tests: Path) -> list[str]:
    names = module_names(tests)
    return [line for path in sorted(tests.rglob("*.py")) for line in imports_of_tests(path, names)]


def test_no_test_module_imports_another():
    found = violations(TESTS)
    assert not found, ("a test module imports another; move what they share to tests/support/ (a module the "
                       "tests import as a library) or to a fixture of tests/conftest.py:\n" + "\n".join(found))


def test_the_check_finds_each_way_of_importing_a_test_module(tmp_path):
    tests = tmp_path / "tests"
    (tests / "store").mkdir(parents=True)
    (tests / "support").mkdir()
    (tests / "store" / "test_store.py").write_text("def test_x():\n    pass\n")
    (tests / "support" / "helpers.py").write_text("X = 1\n")
    lines = ["import test_store", "from test_store import test_x", "from tests.store.test_store import test_x",
             "from tests.store import test_store", "from .test_store import test_x", "from . import test_store"]
    (tests / "store" / "test_other.py").write_text("\n".join(lines + ["from tests.support.helpers import X"]) + "\n")
    found = violations(tests)
    assert [line.split(": ", 1)[0].rsplit(":", 1)[1] for line in found] == [str(n) for n in range(1, 7)], found


# The package(s) each test folder is about (docs/contributing.md): a package is covered when a fast test
# imports it, directly or through tests/support/, or lives in its folder (those reached through the
# command line, e.g. the GenoM reader through `init --from-genom`).
AREAS = {
    "basics": ["harness"],
    "target": ["harness.target", "harness.target.genom"],
    "sut/simulated": ["harness.sut.simulated"],
    "sut/dala": ["harness.sut.dala"],
    "sut/external": ["harness.sut", "harness.sut.external"],
    "sut/ros": ["harness.sut.ros", "harness.sut.roscommon", "harness.sut.bags"],
    "sut/ros2": ["harness.sut.ros2"],
    "dispatch": ["harness.dispatch"],
    "store": ["harness.store"],
    "analysis": ["harness.analysis"],
    "mutator": ["harness.mutator"],
    "campaign": ["harness.campaign"],
    "report": ["harness.report"],
    "report/browser": ["harness.report"],
    "project": ["harness"],
    "hostile": ["harness"],  # the corpus of hostile inputs, every command's (with its cases beside it)
}


def packages() -> set[str]:
    """Every package of harness/: each folder with an __init__.py, as a dotted name."""
    return {".".join(init.parent.relative_to(ROOT).parts) for init in (ROOT / "harness").rglob("__init__.py")}


def imported(path: Path) -> set[str]:
    """The modules `path` imports, and those the modules of tests/support/ it imports import."""
    modules, seen, todo = set(), set(), [path]
    while todo:
        current = todo.pop()
        seen.add(current)
        for node in ast.walk(ast.parse(current.read_text(), str(current))):
            if isinstance(node, ast.Import):
                modules |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                modules |= {node.module} | {f"{node.module}.{alias.name}" for alias in node.names}
        support = {ROOT.joinpath(*m.split(".")).with_suffix(".py") for m in modules if m.startswith("tests.support.")}
        todo += [s for s in support if s.exists() and s not in seen]
    return modules


def covered(path: Path, known: set[str]) -> set[str]:
    folder = "/".join(path.parent.relative_to(TESTS).parts)
    return ({p for p in known for m in imported(path) if m == p or m.startswith(p + ".")}
            | set(AREAS.get(folder, [])))


def test_every_test_folder_names_packages_that_exist():
    folders = {"/".join(p.parent.relative_to(TESTS).parts) for p in TESTS.rglob("test_*.py")}
    assert folders <= AREAS.keys(), f"add {sorted(folders - AREAS.keys())} to AREAS"
    stale = sorted(p for names in AREAS.values() for p in names if p not in packages())
    assert not stale, f"AREAS names packages that harness/ no longer has: {stale}"


@pytest.mark.slow
def test_the_fast_suite_covers_every_package_of_harness():
    collected = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-m", "not slow",
                                "-p", "no:cacheprovider", str(TESTS)], cwd=ROOT, capture_output=True, text=True)
    assert collected.returncode == 0, collected.stdout[-3000:] + collected.stderr[-3000:]
    files = {ROOT / line.split("::")[0] for line in collected.stdout.splitlines() if "::" in line}
    assert len(files) > 20, collected.stdout[-3000:]
    known = packages()
    missing = known - set().union(*(covered(f, known) for f in files))
    assert not missing, (f"no test of the fast suite covers {sorted(missing)}: give each package a test that is "
                         "not marked slow, in its folder or importing it (docs/contributing.md)")


@pytest.mark.slow
def test_the_counts_readme_and_contributing_state_are_the_suites():
    fast, every = counts.collected("not slow"), counts.collected()
    for path in counts.STATED:
        assert counts.stated(path.read_text()) == (fast, every), f"{path.name} states other counts: run make counts"


def test_the_counts_are_written_where_they_are_stated():
    text = "runs `pytest -m \"not slow\"`: 1,042 of the\nsuite's 1,259 tests, every package"
    assert counts.stated(text) == (1042, 1259)
    assert counts.written(text, 1100, 1300) == "runs `pytest -m \"not slow\"`: 1,100 of the\nsuite's 1,300 tests, every package"
