import signal

import pytest

from harness import DEFAULT_MISSION_DIR, cli
from harness.target.interface import load_interface, load_properties


@pytest.fixture(scope="session")
def interface():
    return load_interface(DEFAULT_MISSION_DIR / "interface.toml")


@pytest.fixture(scope="session")
def properties(interface):
    return load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)


@pytest.fixture(scope="session")
def campaign_store(tmp_path_factory):
    """A real, analysed campaign store (seed 7 gives a hung trace, FNs and an FP); tests only read it."""
    db = tmp_path_factory.mktemp("campaign") / "campaign.duckdb"
    assert cli.main(["campaign", "--mutants", "5", "--sut", "genom,bip-a", "--seed", "7", "--jobs", "1",
                     "--db", str(db)]) == 0
    return db


def pytest_report_header():
    """The versions of the project's dependencies this run tests (a fresh .venv has the newest its ranges allow)."""
    import re
    import tomllib
    from importlib.metadata import version
    from tests.support.paths import ROOT
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = [re.match(r"[\w.-]+", r).group(0) for r in project["dependencies"]]
    return "untimely dependencies: " + ", ".join(f"{n} {version(n)}" for n in names)


def pytest_configure(config):
    """Ctrl-C reaches the processes the tests start, however the suite itself was started: a shell
    runs a background job (`make test &` in a script) with SIGINT ignored, and a process started
    with SIGINT ignored keeps ignoring it, so the tests that stop the bench with SIGINT saw it run
    on. A handler here (not SIG_IGN) is reset to the default in every child the suite starts."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
