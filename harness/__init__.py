"""Untimely: an input-timing robustness test bench for robot functional layers."""
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

try:
    __version__ = version("untimely")
except PackageNotFoundError:  # imported from a checkout that was never installed
    __version__ = "unknown"
