"""What an analysis changed: verdict transitions and Tables II-IV, on the paper's own story.

GenoM's undocumented feature: every Init interrupts the running activities of its module. With
AIB as written, genom's interruption by an Init is an FP. Adding the Init to AIB's dominators
turns it into a TP, and a BIP-like variant, which lets the activity end ok, gets an FN instead
of a TN: its AIB true-positive rate drops.
"""
import dataclasses
import json
import shutil
import tomllib

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.cli import main
from harness.analysis.diff import changes
from harness.store.database import connect
from harness.trace import Trace
from tests.support.traces import INTERFACE, PROPERTIES, judged_traces

EPSILON = 0.01
AIB = PROPERTIES["AIB(ndd.GotoPosition)"]
WITH_INIT = dataclasses.replace(AIB, y=AIB.y + ("ndd.Init",))


def _trace(sut: str, *events) -> Trace:
    trace = Trace(sut=sut, seed=0)
    services = {}
    for seq, (t, kind, rqst_id, what) in enumerate(events, 1):
        if kind == "request":
            services[rqst_id] = what
        module, service = services[rqst_id].split(".")
        trace.events.append((seq, t, kind, rqst_id, module, service, None, None if kind == "request" else what))
    return trace


def _story_store(path=":memory:"):
    """genom: an Init interrupts the GotoPosition. bip-a: the Init lets it run (ok); a Stop interrupts
    another GotoPosition (TP)."""
    genom = _trace("genom", (0.0, "request", 1, "ndd.GotoPosition"), (1.0, "request", 2, "ndd.Init"),
                   (1.05, "final", 1, "interrupted"), (1.5, "final", 2, "ok"))
    bip_init = _trace("bip-a", (0.0, "request", 1, "ndd.GotoPosition"), (1.0, "request", 2, "ndd.Init"),
                      (1.5, "final", 2, "ok"), (3.0, "final", 1, "ok"))
    bip_stop = _trace("bip-a", (0.0, "request", 1, "ndd.GotoPosition"), (1.0, "request", 2, "ndd.Stop"),
                      (1.05, "final", 1, "interrupted"), (1.1, "final", 2, "ok"))
    return judged_traces("story", [(genom, None), (bip_init, None), (bip_stop, None)], [AIB], EPSILON, path)


def test_a_second_analysis_after_one_without_verdicts_is_no_first_analysis():
    """Issue 19: a first analysis that judged nothing (the wrong properties) made the second say 'first'."""
    con = _story_store()
    materialise(con, [PROPERTIES["PEX(antenna)"]], EPSILON, INTERFACE)  # no antenna request: no verdict
    materialise(con, [AIB], EPSILON, INTERFACE)
    text = changes(con)
    assert "first analysis" not in text and text.startswith("Changes made by analysis 3")
    assert "3 verdicts changed" in text


def test_adding_init_to_the_dominators_moves_genoms_fp_and_bips_tn():
    con = _story_store()
    assert "first analysis" in changes(con)
    materialise(con, [WITH_INIT], EPSILON, INTERFACE)
    assert con.execute("select * from verdict_transitions order by sut").fetchall() == [
        ("bip-a", "AIB(ndd.GotoPosition)", "AIB", "TN", "FN", 1),
        ("genom", "AIB(ndd.GotoPosition)", "AIB", "FP", "TP", 1)]
    changed = {(sut, family, table, measure): (before, after) for sut, family, table, measure, before, after
               in con.execute("select * from table_changes").fetchall()}
    assert changed == {
        ("genom", "All", "II", "with_fp"): (1, 0), ("genom", "All", "II", "bad"): (1, 0),
        ("genom", "All", "II", "t_rob"): (0, 1),
        ("bip-a", "All", "II", "with_fn"): (0, 1), ("bip-a", "All", "II", "bad"): (0, 1),
        ("bip-a", "All", "II", "t_rob"): (1, 0.5),
        ("genom", "AIB", "III", "tp_rate"): (None, 1), ("genom", "All", "III", "tp_rate"): (None, 1),
        ("bip-a", "AIB", "III", "tp_rate"): (1, 0.5), ("bip-a", "All", "III", "tp_rate"): (1, 0.5),
        ("genom", "AIB", "IV", "fp_rate"): (1, None), ("genom", "All", "IV", "fp_rate"): (1, None),
        ("bip-a", "AIB", "IV", "fp_rate"): (0, None), ("bip-a", "All", "IV", "fp_rate"): (0, None)}
    text = changes(con)
    assert "Changes made by analysis 2 (epsilon 0.01 s) to the verdicts of analysis 1" in text
    assert "2 verdicts changed" in text
    assert [line.split() for line in text.splitlines() if line.startswith(("genom ", "bip-a "))] == [
        ["genom", "AIB(ndd.GotoPosition)", "AIB", "FP", "TP", "1"],
        ["bip-a", "AIB(ndd.GotoPosition)", "AIB", "TN", "FN", "1"]]
    assert ["III", "bip-a", "AIB", "tp_rate", "100.0", "50.0"] in [line.split() for line in text.splitlines()]


def test_the_same_analysis_again_changes_nothing():
    con = _story_store()
    materialise(con, [AIB], EPSILON, INTERFACE)
    assert con.execute("select count(*) from verdict_transitions").fetchone()[0] == 0
    assert con.execute("select count(*) from table_changes").fetchone()[0] == 0
    assert changes(con).endswith("none, every verdict is the same.")


def _properties_file(tmp_path, with_init: bool):
    entry = next(e for e in tomllib.loads((DEFAULT_MISSION_DIR / "properties.toml").read_text())["property"]
                 if e["id"] == AIB.id)
    if with_init:
        entry["y"] = entry["y"] + ["ndd.Init"]
    shutil.copy(DEFAULT_MISSION_DIR / "interface.toml", tmp_path / "interface.toml")
    path = tmp_path / "properties.toml"
    path.write_text("[[property]]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in entry.items()))
    return path


def test_analyze_prints_the_changes_and_diff_shows_them_later(tmp_path, capsys):
    db = tmp_path / "store.duckdb"
    _story_store(db).close()
    properties = _properties_file(tmp_path, with_init=True)
    assert main(["analyze", "--db", str(db), "--properties", str(properties)]) == 0
    analysed = capsys.readouterr().out
    printed = analysed[analysed.index("Changes made by analysis 2"):]
    assert "genom  AIB(ndd.GotoPosition)  AIB     FP        TP" in printed
    assert main(["diff", "--db", str(db)]) == 0
    assert capsys.readouterr().out.strip() == printed.strip()


def test_diff_on_a_store_never_analysed_says_what_to_do(tmp_path, capsys):
    db = tmp_path / "store.duckdb"
    connect(db).close()
    assert main(["diff", "--db", str(db)]) == 2
    assert "has no analysis to compare; run python -m harness analyze" in capsys.readouterr().err
