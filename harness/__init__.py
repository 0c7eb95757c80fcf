"""Untimely: an input-timing robustness test bench for robot functional layers."""
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SQL_DIR = ROOT / "sql"
MISSIONS_DIR = ROOT / "missions"
DEFAULT_MISSION_DIR = MISSIONS_DIR / "dala"
DEFAULT_DB = ROOT / "reports" / "campaign.duckdb"
# Margin (seconds) below which a verdict is flagged suspicious, unless --epsilon says otherwise.
DEFAULT_EPSILON_S = 0.01
