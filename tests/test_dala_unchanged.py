"""Dala's figures do not move when the bench changes inside: a small campaign on every variant gives
the very events, world events and verdicts it gave when tests/expected/dala_campaign.json was made
(before the layer's knowledge moved into missions/dala/layer.toml). Regenerate the file only for a
change that is meant to alter Dala's behaviour: `python tests/test_dala_unchanged.py`."""
import hashlib
import json
import sys
from pathlib import Path

from harness import DEFAULT_MISSION_DIR
from harness.cli import main as cli

EXPECTED = Path(__file__).parent / "expected" / "dala_campaign.json"
ARGS = ["--mutants", "12", "--seed", "7", "--sut", "genom,bip-a,bip-b,bare,reference", "--jobs", "2"]


def _digest(con, query: str) -> str:
    rows = con.execute(query).fetchall()
    return hashlib.sha256(json.dumps(rows, default=str).encode()).hexdigest()


def fingerprint(db: Path) -> dict:
    import duckdb
    con = duckdb.connect(str(db), read_only=True)
    try:
        return {
            "traces": con.execute("select sut, outcome, count(*) from traces group by all order by all").fetchall(),
            "verdicts": con.execute("select family, verdict, count(*) from verdicts group by all order by all")
                           .fetchall(),
            "events": _digest(con, "select trace_id, seq, round(t, 9), kind, rqst_id, module, service, args, reply "
                                   "from events order by trace_id, seq"),
            "world_events": _digest(con, "select trace_id, round(t, 9), kind, detail from world_events "
                                         "order by all"),
            "verdict_rows": _digest(con, "select trace_id, property_id, rqst_id, c_holds, verdict, "
                                         "round(margin_s, 9), suspicious from verdicts order by all"),
        }
    finally:
        con.close()


def run_campaign(db: Path) -> dict:
    assert cli(["campaign", "--mission", str(DEFAULT_MISSION_DIR), "--db", str(db), *ARGS]) == 0
    return json.loads(json.dumps(fingerprint(db)))  # tuples as lists, as stored


def test_dala_campaign_is_unchanged(tmp_path):
    assert run_campaign(tmp_path / "c.duckdb") == json.loads(EXPECTED.read_text())


if __name__ == "__main__":
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        EXPECTED.write_text(json.dumps(run_campaign(Path(folder) / "c.duckdb"), indent=1) + "\n")
    print(f"wrote {EXPECTED}", file=sys.stderr)
