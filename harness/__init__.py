"""Untimely: an input-timing robustness test bench for robot functional layers."""
import re
from importlib.metadata import PackageNotFoundError, version
from importlib.resources import files
from pathlib import Path

# The folder holding the package: the checkout in an editable install, site-packages in a wheel.
ROOT = Path(__file__).resolve().parent.parent
# sql/ and missions/ are installed as the packages harness.sql and harness.missions (pyproject.toml),
# so the checkout and an installed wheel find them the same way.
SQL_DIR = Path(str(files("harness.sql")))
MISSIONS_DIR = Path(str(files("harness.missions")))
DEFAULT_MISSION_DIR = MISSIONS_DIR / "dala"
# Relative: the store of the folder the command runs in.
DEFAULT_DB = Path("reports") / "campaign.duckdb"
# Margin (seconds) below which a verdict is flagged suspicious, unless --epsilon says otherwise.
DEFAULT_EPSILON_S = 0.01
# Modules that moved into harness/sut/: a command recorded in an older store (campaigns.config), or
# a suts.toml or layer.toml written before the move, names them by the old name, which still runs.
MOVED_MODULES = {"harness.adapters.sim": "harness.sut.simulated", "harness.adapters.ros2": "harness.sut.ros2",
                 "harness.adapters.ros": "harness.sut.ros", "harness.sim.dala": "harness.sut.dala",
                 "harness.sim": "harness.sut.simulated"}
_MOVED = re.compile(r"(?<![\w.])(" + "|".join(map(re.escape, MOVED_MODULES)) + r")\b")  # not my.harness.sim


def current_modules(text: str) -> str:
    """`text` (a module name, or a command line) with every moved module under its current name."""
    return _MOVED.sub(lambda m: MOVED_MODULES[m[1]], text)


try:
    __version__ = version("untimely")
except PackageNotFoundError:  # imported from a checkout that was never installed
    __version__ = "unknown"
