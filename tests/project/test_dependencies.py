"""Every dependency names the major versions it is supported on, and the installed ones are inside them.

`make venv` installs the newest versions the ranges allow (`--upgrade-strategy eager`), so the suite
run on a fresh machine, as CI's is, tests exactly those; the versions it ran on head pytest's output."""
import tomllib
from importlib.metadata import version

from packaging.requirements import Requirement
from tests.support.paths import ROOT

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
CALENDAR_VERSIONED = {"pytz"}  # a new year's release is no new major version


def requirements() -> list[Requirement]:
    extras = [r for group in PYPROJECT["optional-dependencies"].values() for r in group]
    return [Requirement(r) for r in PYPROJECT["dependencies"] + extras if not r.startswith("untimely[")]


def test_every_dependency_has_a_supported_major_range():
    for req in requirements():
        operators = {spec.operator for spec in req.specifier}
        assert ">=" in operators or "~=" in operators, f"{req}: give the oldest supported version"
        if req.name not in CALENDAR_VERSIONED:
            assert "<" in operators or "~=" in operators, f"{req}: give the first unsupported major version"


def test_the_installed_versions_are_in_range():
    for req in requirements():
        assert req.specifier.contains(version(req.name), prereleases=True), (req, version(req.name))
