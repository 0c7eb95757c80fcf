"""Hand-made traces with the verdicts they must get, in a small line format (*.trace here).

    mission missions/manipulator                # optional, first: another target than Dala
    use PEX(rflex) AIB(ndd.GotoPosition)        # the properties judged in this file
    trace pc_true_accepted sut=genom outcome=hung   # a trace: label, optional sut, outcome, end
                                                # (sim_s, seconds) and golden=yes (a golden run's)
    0.0 request 1 rflex.Init                    # t kind rqst_id module.Service
    0.5 final   1 ok                            # t final rqst_id reply (service from the request)
    2.5 request 3 ndd.GotoPosition x=9 y=nan    # arguments as a mission script writes them
    1.5 request 2 rflex.TrackSpeedStart  => PEX(rflex) TN true 1.0
    2.0 final   2 ok

Events get seq in line order. After `=>` on a request line come the expected verdict rows
of that request, separated by `;`: property id, verdict, c_holds (true, false, null),
margin_s (seconds, or - for NULL), and `suspicious` when the row must be flagged (at the
fixtures' epsilon, 10 ms); a row without it must not be. Every verdict row of the trace must be listed.
Properties come from missions/dala/properties.toml and tests/traces/properties.toml, or from the
properties.toml of the file's `mission` folder (whose interface then gives the reply classes).
"""
from __future__ import annotations

import json

from dataclasses import dataclass, field
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.analysis.analyzer import materialise
from harness.target.interface import Interface, load_interface, load_properties
from harness.target.mission import load_mission
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import ImportRecord
from harness.trace import Trace
from tests.support.paths import TRACES

HERE = TRACES
INTERFACE = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
PROPERTIES = {p.id: p for path in (DEFAULT_MISSION_DIR / "properties.toml", HERE / "properties.toml")
              for p in load_properties(path, INTERFACE)}
BOOLEANS = {"true": True, "false": False, "null": None}


@dataclass
class Case:
    label: str
    trace: Trace
    # (property_id, rqst_id) -> (verdict, c_holds, margin_s)
    expected: dict[tuple[str, int], tuple[str, bool | None, float | None]] = field(default_factory=dict)
    flagged: set[tuple[str, int]] = field(default_factory=set)  # the rows marked suspicious
    services: dict[int, str] = field(default_factory=dict)  # rqst_id -> "module.Service"
    golden: bool = False  # the trace of a golden script (a derived deadline reads those)


@dataclass
class Fixture:
    path: Path
    properties: list
    cases: list[Case]
    interface: Interface = INTERFACE


def _expect(case: Case, text: str, rqst_id: int, where: str, known: dict) -> None:
    for item in text.split(";"):
        property_id, verdict, c_holds, margin, *flag = item.split()
        if property_id not in known or c_holds not in BOOLEANS or flag not in ([], ["suspicious"]):
            raise ValueError(f"{where}: bad expectation {item.strip()!r}")
        case.expected[(property_id, rqst_id)] = (verdict, BOOLEANS[c_holds], None if margin == "-" else float(margin))
        if flag:
            case.flagged.add((property_id, rqst_id))


def load(path: Path) -> Fixture:
    properties, cases, known, interface = [], [], PROPERTIES, INTERFACE
    for n, raw in enumerate(path.read_text().splitlines(), 1):
        line, _, expect = raw.split("#")[0].partition("=>")
        words, where = line.split(), f"{path.name}:{n}"
        if not words:
            continue
        if words[0] == "mission":
            mission = load_mission(ROOT / words[1])
            interface, known = mission.interface, {p.id: p for p in mission.properties()}
        elif words[0] == "use":
            properties = [known[w] for w in words[1:]]
        elif words[0] == "trace":
            options = dict(w.split("=") for w in words[2:])
            cases.append(Case(words[1], Trace(sut=options.get("sut", "fixture"), seed=0,
                                              outcome=options.get("outcome", "completed"),
                                              sim_s=float(options.get("end", 0))),
                              golden=options.get("golden") == "yes"))
        else:
            case, (t, kind, rqst_id, what), written = cases[-1], words[:4], words[4:]
            rqst_id, args = int(rqst_id), None
            if kind == "request":
                case.services[rqst_id] = what
                module, service, reply = *what.split("."), None
                if written:
                    args = json.dumps(interface.services[what].typed(dict(w.split("=", 1) for w in written)))
            else:
                module, service, reply = *case.services[rqst_id].split("."), None if what == "-" else what
            case.trace.events.append((len(case.trace.events) + 1, float(t), kind, rqst_id,
                                      module, service, args, reply))
            if expect.strip():
                _expect(case, expect, rqst_id, where, known)
    return Fixture(path, properties, cases, interface)


def all_fixtures() -> list[Fixture]:
    return [load(p) for p in sorted(HERE.glob("*.trace"))]


def judged_traces(mission: str, traces: list[tuple[Trace, str | None]], properties: list, epsilon: float,
                  path=":memory:", interface: Interface = INTERFACE, golden: frozenset[int] = frozenset()):
    """A store of one campaign holding `traces`, (trace, label) pairs given ids 1, 2, ... in order,
    judged with `properties`; those whose ids are in `golden` are runs of a golden script (its id theirs)."""
    con = connect(path)
    add_campaign(con, 1, mission, 0, ImportRecord(imported=mission, sha256="none: traces written by a test"))
    add_reply_codes(con, interface)
    for trace_id, (trace, label) in enumerate(traces, 1):
        if trace_id in golden:
            con.execute("insert into scripts values (?, 1, 'golden', null, '[]', '', true, null)", [trace_id])
        insert_trace(con, trace_id, 1, trace_id if trace_id in golden else None, trace, label=label)
    materialise(con, properties, epsilon, interface)
    return con


def judged_store(fixture: Fixture, epsilon: float, path=":memory:"):
    """A store holding the fixture's traces (ids 1, 2, ... in file order), judged with its properties."""
    return judged_traces(str(fixture.path), [(case.trace, case.label) for case in fixture.cases],
                         fixture.properties, epsilon, path, fixture.interface,
                         frozenset(n for n, case in enumerate(fixture.cases, 1) if case.golden))
