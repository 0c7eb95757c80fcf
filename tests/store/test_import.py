"""Importing foreign traces: three formats, integer ids, row checks with line and value, all or nothing."""
import csv
import json
from datetime import datetime

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.cli import main
from harness.errors import InputFileError, StoreError
from harness.store.importer import import_file
from harness.target.interface import load_interface
from harness.store.database import connect

COLUMNS = ["trace_id", "seq", "t", "kind", "rqst_id", "module", "service", "args", "reply", "outcome"]
# Two traces, interleaved as a real log might be; run-b hung with its GotoPosition unanswered.
ROWS = [
    ["run-a", 1, 0.0, "request", 1, "rflex", "Init", None, None, None],
    ["run-b", 1, 0.0, "request", 7, "ndd", "GotoPosition", '{"x": 1.0, "y": 2.0}', None, "hung"],
    ["run-a", 2, 0.5, "final", 1, "rflex", "Init", None, "ok", None],
    ["run-a", 3, 1.0, "request", 2, "rflex", "TrackSpeedStart", None, None, None],
    ["run-a", 4, 1.2, "intermediate", 2, "rflex", "TrackSpeedStart", None, None, None],
    ["run-a", 5, 1.5, "final", 2, "rflex", "TrackSpeedStart", None, "ok", None],
]
TABLES = ("campaigns", "traces", "events", "reply_codes")


def write(path, rows, columns=COLUMNS):
    """The rows in the format the suffix of `path` names."""
    if path.suffix == ".csv":
        with open(path, "w", newline="") as f:
            csv.writer(f).writerows([columns] + [["" if v is None else v for v in r] for r in rows])
    elif path.suffix == ".jsonl":
        path.write_text("".join(json.dumps(dict(zip(columns, r))) + "\n" for r in rows))
    else:
        pq.write_table(pa.table({c: [r[i] for r in rows] for i, c in enumerate(columns)}), path)
    return path


def counts(con):
    return {t: con.execute(f"select count(*) from {t}").fetchone()[0] for t in TABLES}


@pytest.mark.parametrize("suffix", [".csv", ".jsonl", ".parquet"])
def test_each_format_gives_the_same_store(tmp_path, interface, suffix):
    con = connect(":memory:")
    path = write(tmp_path / f"robot{suffix}", ROWS)
    assert import_file(con, path, interface) == (1, 1, 2)
    assert con.execute("select trace_id, label, sut, outcome, sim_s, campaign_id, script_id from traces "
                       "order by 1").fetchall() == [(1, "run-a", "robot", "completed", 1.5, 1, None),
                                                    (2, "run-b", "robot", "hung", 0.0, 1, None)]
    assert con.execute("select * from events order by trace_id, seq").fetchall() == [
        (1, 1, 0.0, "request", 1, "rflex", "Init", None, None),
        (1, 2, 0.5, "final", 1, "rflex", "Init", None, "ok"),
        (1, 3, 1.0, "request", 2, "rflex", "TrackSpeedStart", None, None),
        (1, 4, 1.2, "intermediate", 2, "rflex", "TrackSpeedStart", None, None),
        (1, 5, 1.5, "final", 2, "rflex", "TrackSpeedStart", None, "ok"),
        (2, 1, 0.0, "request", 7, "ndd", "GotoPosition", '{"x": 1.0, "y": 2.0}', None)]
    assert con.execute("select mission, seed from campaigns").fetchall() == [(str(path), 0)]
    assert con.execute("select class from reply_codes where reply = 'interrupted' limit 1").fetchone() == ("Z",)


def test_a_second_import_gets_new_ids_and_is_judged_like_any_trace(tmp_path, interface, properties):
    con = connect(":memory:")
    import_file(con, write(tmp_path / "robot.csv", ROWS), interface)
    assert import_file(con, write(tmp_path / "robot.jsonl", ROWS), interface) == (2, 3, 2)
    materialise(con, properties, 0.01, interface)
    assert con.execute("select trace_id, property_id, verdict from verdicts where module = 'rflex' "
                       "and trace_id = 3 order by property_id").fetchall() == [
        (3, "AIB(rflex.TrackSpeedStart)", "TN"), (3, "PEX(rflex)", "TN"), (3, "PRE(rflex.TrackSpeedStart)", "FN")]


def test_sut_and_outcome_columns_are_optional(tmp_path, interface):
    con = connect(":memory:")
    columns = COLUMNS[:7] + ["reply", "sut"]
    rows = [r[:7] + [r[8], "dala-real"] for r in ROWS if r[0] == "run-a"]
    import_file(con, write(tmp_path / "log.jsonl", rows, columns), interface)
    assert con.execute("select sut, outcome from traces").fetchall() == [("dala-real", "completed")]


def _with(row_index, column, value):
    rows = [list(r) for r in ROWS]
    rows[row_index][COLUMNS.index(column)] = value
    return rows


BAD = [  # rows, the error it must give (CSV: the header is line 1, ROWS[0] is line 2)
    (_with(2, "kind", "finale"), "line 4: kind = 'finale' is not one of request, intermediate, final"),
    (_with(3, "module", "rflx"), "line 5: module = 'rflx' is not a module of the interface"),
    (_with(3, "service", "Fly"), "line 5: service = 'Fly' is not a service of that module"),
    (_with(2, "reply", "fine"), "line 4: reply = 'fine' is not in the reply catalogue of the interface"),
    (_with(2, "reply", None), "line 4: reply is empty: a final reply needs its reply code"),
    (_with(0, "reply", "ok"), "line 2: reply = 'ok' is not allowed on a request"),
    (_with(1, "t", "soon"), "line 3: t = 'soon' is not a time in seconds"),
    (_with(1, "args", "{x: 1"), "line 3: args = '{x: 1' is not JSON"),
    (_with(1, "outcome", "lost"), "line 3: outcome = 'lost' is not one of completed, hung, crashed"),
    (_with(0, "trace_id", None), "line 2: trace_id is empty: every event needs one"),
    (_with(2, "rqst_id", 9), "line 4: final reply to request 9 of trace 'run-a' comes without an earlier request"),
    (_with(3, "seq", 2), "line 5: seq = 2 does not increase after seq = 2 (line 4) in trace 'run-a'"),
    (_with(3, "t", 0.25), "line 5: t = 0.25 goes backwards from t = 0.5 (line 4) in trace 'run-a'"),
    (_with(4, "service", "Stop"), "line 6: intermediate reply names rflex.Stop but request 2 of trace 'run-a' "
                                  "is rflex.TrackSpeedStart"),
    (_with(3, "rqst_id", 1), "line 5: request 1 of trace 'run-a' is sent a second time"),
    (_with(2, "rqst_id", 2**31), "line 4: rqst_id = '2147483648' is out of range: the store keeps rqst_id as a "
                                 "32-bit integer (at most 2147483647); renumber them"),
    (_with(1, "t", "1e300"), "line 3: t = '1e300' is not a time in seconds since the trace started (at most 1e+09 s"),
    (_with(1, "args", '{"x": NaN, "y": "NaN"}'), "line 3: args = '{\"x\": NaN, \"y\": \"NaN\"}' holds NaN or "
                                                  "Infinity, which are no JSON numbers"),
    (_with(1, "args", '{"x": [1, -Infinity]}'), "line 3: args = '{\"x\": [1, -Infinity]}' holds NaN or Infinity"),
]


@pytest.mark.parametrize("rows,message", BAD, ids=[m.split(": ")[1][:40] for _, m in BAD])
def test_a_bad_row_is_reported_with_its_line_and_value_and_nothing_is_written(tmp_path, interface, rows, message):
    con = connect(":memory:")
    import_file(con, write(tmp_path / "before.csv", ROWS), interface)
    before = counts(con)
    with pytest.raises(InputFileError) as caught:
        import_file(con, write(tmp_path / "robot.csv", rows), interface)
    assert str(caught.value).startswith(f"{tmp_path / 'robot.csv'}:{message}")
    assert "nothing was imported" in str(caught.value)
    assert counts(con) == before


def test_every_bad_row_is_listed(tmp_path, interface):
    rows = _with(1, "kind", "req")
    rows[3][COLUMNS.index("module")] = "rflx"
    with pytest.raises(InputFileError) as caught:
        import_file(connect(":memory:"), write(tmp_path / "robot.csv", rows), interface)
    assert f"{tmp_path / 'robot.csv'}:line 5: module = 'rflx'" in str(caught.value).splitlines()[1]


def test_json_lines_and_parquet_number_their_own_lines(tmp_path, interface):
    path = write(tmp_path / "robot.jsonl", _with(2, "kind", "finale"))
    path.write_text("\n" + path.read_text())  # a blank first line still counts
    with pytest.raises(InputFileError, match=r"robot.jsonl:line 4: kind = 'finale'"):
        import_file(connect(":memory:"), path, interface)
    with pytest.raises(InputFileError, match=r"robot.parquet:row 3: kind = 'finale'"):
        import_file(connect(":memory:"), write(tmp_path / "robot.parquet", _with(2, "kind", "finale")), interface)
    (tmp_path / "broken.jsonl").write_text('{"trace_id": "a"}\n{"trace_id": \n')
    with pytest.raises(InputFileError, match=r"broken.jsonl:line 2: not valid JSON"):
        import_file(connect(":memory:"), tmp_path / "broken.jsonl", interface)


def test_unreadable_files_are_refused(tmp_path, interface):
    con = connect(":memory:")
    with pytest.raises(InputFileError, match="missing rqst_id, module"):
        import_file(con, write(tmp_path / "short.csv", [r[:4] for r in ROWS], COLUMNS[:4]), interface)
    with pytest.raises(InputFileError, match=r"unknown format '.xml'"):
        import_file(con, write(tmp_path / "log.xml", ROWS), interface)
    with pytest.raises(InputFileError, match="file not found"):
        import_file(con, tmp_path / "none.csv", interface)
    with pytest.raises(InputFileError, match="no events"):
        import_file(con, write(tmp_path / "empty.csv", []), interface)


def test_hostile_files_are_refused_naming_line_and_value(tmp_path, interface):
    """Issue 19: these raised tracebacks (RecursionError, TypeError, an ambiguous column)."""
    con = connect(":memory:")
    deep = tmp_path / "deep.jsonl"
    deep.write_text(json.dumps(dict(zip(COLUMNS, ROWS[0]))) + "\n" + "[" * 200_000 + "]" * 200_000 + "\n")
    with pytest.raises(InputFileError, match=r"deep.jsonl:line 2: JSON nested too deeply to be an event"):
        import_file(con, deep, interface)
    stamped = tmp_path / "stamped.parquet"
    args = [None, {"at": datetime(2024, 5, 1, 12, 0)}] + [None] * (len(ROWS) - 2)
    pq.write_table(pa.table({**{c: [r[i] for r in ROWS] for i, c in enumerate(COLUMNS) if c != "args"},
                             "args": args}), stamped)
    with pytest.raises(InputFileError, match=r"stamped.parquet:row 2: args holds \{'at': datetime.datetime\(2024, 5, 1, "
                                             r"12, 0\)\}, which is no JSON value .*give arguments as numbers"):
        import_file(con, stamped, interface)
    twice = write(tmp_path / "twice.csv", [r + [r[1]] for r in ROWS], COLUMNS + ["seq"])
    with pytest.raises(InputFileError, match=r"twice.csv:1: the header names the column 'seq' twice; keep one"):
        import_file(con, twice, interface)
    assert con.execute("select count(*) from traces").fetchone()[0] == 0


def test_a_reply_class_conflicting_with_the_store_rolls_back(tmp_path, interface):
    con = connect(":memory:")
    import_file(con, write(tmp_path / "robot.csv", ROWS), interface)
    before = counts(con)
    changed = tmp_path / "interface.toml"
    changed.write_text((DEFAULT_MISSION_DIR / "interface.toml").read_text()
                       .replace('interrupted = "Z"', 'interrupted = "T"'))
    with pytest.raises(StoreError, match="reply 'interrupted' of .* has class 'T'"):
        import_file(con, write(tmp_path / "robot.jsonl", ROWS), load_interface(changed))
    assert counts(con) == before


def test_import_command(tmp_path, capsys):
    path, db = write(tmp_path / "robot.csv", ROWS), tmp_path / "store.duckdb"
    assert main(["import", str(path), "--interface", str(DEFAULT_MISSION_DIR / "interface.toml"),
                 "--db", str(db)]) == 0
    assert "Imported 2 traces (6 events)" in capsys.readouterr().out
    assert main(["import", str(write(tmp_path / "bad.csv", _with(2, "kind", "x"))), "--interface",
                 str(DEFAULT_MISSION_DIR / "interface.toml"), "--db", str(db)]) == 2
    assert "bad.csv:line 4: kind = 'x'" in capsys.readouterr().err


def test_the_same_file_twice_is_refused_and_nothing_is_written(tmp_path, interface):
    con = connect(":memory:")
    path = write(tmp_path / "robot.csv", ROWS)
    import_file(con, path, interface)
    before = counts(con)
    copy = tmp_path / "renamed.csv"
    copy.write_bytes(path.read_bytes())
    with pytest.raises(InputFileError, match=r"renamed.csv: these events were already imported on .* as campaign 1 "
                                             r"\(trace ids 1-2\); nothing was imported"):
        import_file(con, copy, interface)
    assert counts(con) == before
