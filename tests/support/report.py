"""A small hand-made store (six traces of three variants and an imported log), judged, its report
written, and an HTML page as the tests read it."""
from __future__ import annotations

import json
from html.parser import HTMLParser
from pathlib import Path

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.report import build as report
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import CampaignRecord
from harness.store.sql import render_bench
from harness.target.interface import load_interface, load_properties
from harness.trace import Trace

GOLDEN = """send rflex.Init as ri
send ndd.Init as ni
wait all
send rflex.SetMode mode=velocity as mode
send ndd.SetParams speed=0.6 as nav
wait all
send rflex.TrackSpeedStart as track
send ndd.GotoPosition x=9 y=4 as site
wait site
send ndd.Stop as ns
send rflex.Stop as rs
wait all
"""


SWAPPED = GOLDEN.replace("send ndd.SetParams speed=0.6 as nav\nwait all\n", "wait all\n").replace(
    "wait site\n", "wait site\nsend ndd.SetParams speed=0.6 as nav\n")


REINIT = GOLDEN.replace("wait site\n", "send rflex.Init as ri2\nwait site\n")


# (module, service, args, requested at, final reply at or None, reply)
BASE = [("rflex", "Init", None, 0.0, 0.5, "ok"), ("ndd", "Init", None, 0.0, 0.4, "ok"),
        ("rflex", "SetMode", {"mode": "velocity"}, 0.6, 0.6, "ok"),
        ("ndd", "SetParams", {"speed": 0.6}, 0.6, 0.6, "ok")]


DRIVE = [("rflex", "TrackSpeedStart", None, 1.0, 12.0, "interrupted"),
         ("ndd", "GotoPosition", {"x": 9, "y": 4}, 1.0, 11.0, "ok"),
         ("ndd", "Stop", None, 11.5, 11.6, "ok"), ("rflex", "Stop", None, 11.999, 12.05, "ok")]


TRACES = {  # trace_id: (sut, outcome, script_id, requests, world events)
    1: ("genom", "completed", 1, BASE + DRIVE, []),
    2: ("genom", "completed", 2,  # the Stop or the Init, 1-2 ms apart, interrupted TrackSpeedStart: suspicious
        BASE[:3] + DRIVE + [("ndd", "SetParams", {"speed": 0.6}, 11.2, 11.2, "ok"),
                            ("rflex", "Init", None, 11.998, 12.5, "ok")],
        [(6.5, "collision", {"with": "rock"})]),
    3: ("genom", "completed", 3,  # genom's quirk: Init interrupts the running TrackSpeedStart
        BASE + [("rflex", "TrackSpeedStart", None, 1.0, 5.01, "interrupted")] + DRIVE[1:3]
        + [("rflex", "Init", None, 5.0, 5.5, "ok"), ("rflex", "Stop", None, 11.999, 12.05, "ok")], []),
    4: ("bip-a", "completed", 1, BASE + DRIVE, []),
    5: ("bip-a", "hung", 2, BASE[:3] + [("rflex", "TrackSpeedStart", None, 1.0, None, None),
                                          ("ndd", "GotoPosition", {"x": 9, "y": 4}, 1.0, 1.0, "disallowed"),
                                          ("antenna", "Communication", {"duration": 10}, 2.0, None, None)],
        [(3.0, "link_lost", {})]),
    6: ("reference", "completed", None, BASE, []),  # imported, only Init and control: no verdict
    7: ("bip-a", "completed", 3, BASE + DRIVE, []),  # good, but inverted on the internal timeline
}


# The layer took ndd.SetParams only after ndd.GotoPosition: PRE(ndd.GotoPosition) is TN observed, FN inside.
INTERNAL = {7: BASE[:3] + [("ndd", "SetParams", {"speed": 0.6}, 1.001, 1.001, "ok")] + DRIVE}


def _events(requests) -> list[tuple]:
    """Event rows (seq, t, kind, rqst_id, module, service, args, reply) from request tuples."""
    raw = []
    for rqst_id, (module, service, args, t0, t1, reply) in enumerate(requests, start=1):
        text = json.dumps(args) if args else None
        raw.append((t0, 0, "request", rqst_id, module, service, text, None))
        if t1 is not None:
            raw.append((t1, 1, "final", rqst_id, module, service, text, reply))
    raw.sort(key=lambda e: (e[0], e[1], e[3]))
    return [(seq, t, kind, r, m, s, a, reply) for seq, (t, _, kind, r, m, s, a, reply) in enumerate(raw)]


def make_store(path) -> None:
    """A small campaign: a golden script, two mutants and an invalid one, five traces on two variants
    (an FN, an FP, a hang, suspicious TPs, world events) and an imported trace without verdicts."""
    con = connect(path)
    add_campaign(con, 1, "missions/dala", 7, CampaignRecord(mission="missions/dala", sut=["genom", "bip-a"], mutants=3,
                                                             seed=7, ops_per_mutant=1))
    add_reply_codes(con, load_interface(DEFAULT_MISSION_DIR / "interface.toml"))
    scripts = [(1, "golden", None, [], GOLDEN, True, None),
               (2, "mutant", 1, [{"op": "swap", "lines": [5, 9]}], SWAPPED, True, None),
               (3, "mutant", 1, [{"op": "insert", "line": 9}], REINIT, True, None),
               (4, "mutant", 1, [{"op": "delete", "line": 1}], GOLDEN[22:], False,
                "line 2: unknown handle 'ri'; send it before waiting on it")]
    for sid, kind, parent, ops, body, valid, reason in scripts:
        con.execute("insert into scripts (script_id, campaign_id, kind, parent, mutations, body, valid, "
                    "invalid_reason) values (?, 1, ?, ?, ?, ?, ?, ?)",
                    [sid, kind, parent, json.dumps(ops), body, valid, reason])
    for trace_id, (sut, outcome, script_id, requests, world) in TRACES.items():
        trace = Trace(sut, seed=trace_id if script_id else None, outcome=outcome,
                      sim_s=12.1 if outcome == "completed" else 30.0, wall_s=0.0011 if outcome == "hung" else 0.01,
                      events=_events(requests), internal_events=_events(INTERNAL.get(trace_id, [])),
                      world_events=[(t, kind, json.dumps(d)) for t, kind, d in world])
        insert_trace(con, trace_id, 1, script_id, trace, label=None if script_id else "robot-log")
    con.close()


def analysed_store(path, epsilon: float = 0.01, mission: Path = DEFAULT_MISSION_DIR):
    """make_store, judged by the analyzer with the properties of `mission` (Dala's)."""
    make_store(path)
    interface = load_interface(mission / "interface.toml")
    con = connect(path)
    materialise(con, load_properties(mission / "properties.toml", interface), epsilon, interface,
                mission / "properties.toml")
    con.close()
    return path


def copied_store(path, copies: int) -> Path:
    """make_store with its traces copied `copies` times under new ids (a store of many traces in
    seconds, as bench/report_bench.py makes one), judged with Dala's properties."""
    make_store(path)
    con = connect(path)
    top = con.execute("select max(trace_id) from traces").fetchone()[0]
    con.execute(render_bench("copied_traces", copies=copies, top=top))
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    materialise(con, load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface), 0.01, interface)
    con.close()
    return Path(path)


def write_report(db, out, traces=()) -> Path:
    """The whole report, or with `traces` only their pages (on demand)."""
    report.main(str(db), str(out), list(traces))
    return Path(out)


class Page(HTMLParser):
    """An HTML page as the tests read it: its elements, and each table's rows of (text, href) cells."""

    def __init__(self, text: str):
        super().__init__()
        self.elements: list[tuple[str, dict]] = []
        self.tables: dict[str, list[list[tuple[str, str | None]]]] = {}
        self._rows = self._cell = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.elements.append((tag, attrs))
        if tag == "table":
            self._rows = self.tables.setdefault(attrs.get("id"), [])
        elif tag == "tr" and self._rows is not None:
            self._rows.append([])
        elif tag in ("td", "th") and self._rows is not None:
            self._cell = ["", None]
        elif tag == "a" and self._cell is not None:
            self._cell[1] = attrs.get("href")

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[0] += data

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._rows[-1].append((self._cell[0].strip(), self._cell[1]))
            self._cell = None
        elif tag == "table":
            self._rows = None

    def with_class(self, css: str) -> list[dict]:
        return [attrs for _, attrs in self.elements if css in (attrs.get("class") or "").split()]

    def texts(self, table: str) -> list[list[str]]:
        return [[text for text, _ in row] for row in self.tables[table]]
