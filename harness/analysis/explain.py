"""`python -m harness explain TRACE_ID PROPERTY [RQST_ID]`: why a verdict is what it is.

For each judged request it prints the request and its final reply (with the reply's class),
the verdict, C and its margin, and every item that could decide C: the y(j) requests (ES, EE
and their compositions, VAL's running activities), the services q of Q (PC) with their events,
or the arguments of x(i) (VAL) with their values and domains, whether each makes C
false, and how far it would have to move to change that. The pairs come from the property's
own oracle query (render_property(..., explain=...)), so the explanation cannot drift from
the verdict. The report's trace pages show the same text for their FN, FP and suspicious verdicts.
"""
from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path

import duckdb

from harness.errors import StoreError, UntimelyError
from harness.target.interface import Interface, Property, load_interface, load_properties
from harness.analysis.oracles import Judging, render_property
from harness.store import analysis_reads
from harness.store.reads import exists, relations, require_analysis, trace_epsilons
from harness.analysis.provenance import default_properties
from harness.store.database import connect
from harness.target.mission import INTERFACE_FILE
from harness.textable import format_table

Key = tuple[int, str, int]  # (trace_id, property_id, rqst_id): one verdict row
ARGUMENT_ITEM = "arg "  # how a value-domain oracle names an argument among its items (sql/oracles/val.sql)
SPAN_ITEM = "state"  # how IN and OUT name the state x(i) stands in (sql/oracles/_span.sql)
EPSILON_SOURCES = {"pings": ", measured by the trace's pings", "taken": ", a taken reply to every request"}
DEADLINE_ITEM = "deadline"  # how the ROS 2 types name their deadline, its events in `detail` (sql/oracles/_deadline.sql)


def judged_files(con, properties: str | None = None) -> tuple[Path, Path]:
    """The properties file (`properties` if given) and interface file the stored verdicts were made
    from: the last analysis's when they are recorded and still there, else the campaign mission's."""
    found = analysis_reads.judged_file_paths(con) if exists(con, "analysis_files") else {}
    if properties is not None:
        return Path(properties), Path(properties).parent / INTERFACE_FILE
    usable = "properties" in found and Path(found["properties"]).is_file()
    path = Path(found["properties"]) if usable else default_properties(con)
    interface_file = Path(found.get("interface") or path.parent / INTERFACE_FILE) if usable else None
    return path, interface_file or path.parent / INTERFACE_FILE


def judged_properties(con) -> tuple[Interface, dict[str, Property]]:
    """The interface and properties the stored verdicts were made from (judged_files)."""
    path, interface_file = judged_files(con)
    interface = load_interface(interface_file)
    return interface, {p.id: p for p in load_properties(path, interface)}


def _seconds(value) -> str:
    return "-" if value is None else f"{value:.6f}"


def _item_order(pair: dict) -> tuple:
    """Items by part (ES, EE), then request id (y) or service (q): the oracle's query gives them
    in an order that depends on DuckDB's plan and threads."""
    item = str(pair["item"])
    return str(pair.get("part", "")), not item.isdigit(), int(item) if item.isdigit() else 0, item


class Explainer:
    """Explanations of many verdicts at once: one oracle query per property, one read of the
    requests of all the traces concerned."""

    def __init__(self, con, interface: Interface, properties: dict[str, Property]):
        self.con, self.interface, self.properties = con, interface, properties
        self.epsilon = analysis_reads.analysis_epsilon(con)
        tables = relations(con)  # a store read as it is may lack the newer ones
        self.runs, self.taken = "trace_runs" in tables, "taken_events" in tables
        # the epsilon each trace was judged with (its pings' for a real-time run), not the analysis's alone
        self.trace_epsilon = trace_epsilons(con) if "trace_epsilon" in tables else {}

    def explain(self, keys: list[Key]) -> dict[Key, str]:
        keys = [k for k in keys if k[1] in self.properties]
        if not keys:
            return {}
        # a request the SUT replied `taken` to stands at that reply (view requests): its sending is another instant
        found = analysis_reads.explained_requests(self.con, {t for t, _, _ in keys}, self.taken)
        requests = {(r[0], r[1]): r[2:8] for r in found}
        self.sent = {(r[0], r[1]): r[8] for r in found if r[9]}  # the requests placed at their taken reply
        verdicts = {(t, p, r): rest for t, p, r, *rest in analysis_reads.verdict_rows(self.con, keys)}
        pairs: dict[Key, list[dict]] = defaultdict(list)
        failed: dict[str, str] = {}  # property id -> why its oracle could not explain
        for property_id in dict.fromkeys(p for _, p, _ in keys):
            wanted = [(t, r) for t, p, r in keys if p == property_id]
            try:
                judging = Judging("events", self.epsilon, self.interface, list(self.properties.values()),
                                  runs=self.runs, taken=self.taken)
                cursor = self.con.execute(render_property(self.properties[property_id], judging, explain=wanted))
            except duckdb.Error as e:  # one property's failing oracle must not hide the others' explanations
                failed[property_id] = str(e).split("\n")[0]
                continue
            names = [d[0] for d in cursor.description]
            for row in cursor.fetchall():
                pair = dict(zip(names, row))
                pairs[(pair["trace_id"], property_id, pair["rqst_id"])].append(pair)
        for found in pairs.values():
            found.sort(key=_item_order)
        oks = defaultdict(list)  # (trace, service) -> the instants of its ok final replies
        for (trace_id, _), (service, _, final_t, reply, _, _) in requests.items():
            if reply == "ok":
                oks[(trace_id, service)].append(final_t)
        return {k: self._failed(k, verdicts[k], failed[k[1]]) if k[1] in failed
                else self._text(k, verdicts[k], requests, oks, pairs[k]) for k in keys if k in verdicts}

    @staticmethod
    def _failed(key: Key, verdict_row: tuple, error: str) -> str:
        trace_id, property_id, rqst_id = key
        return (f"{property_id} on request {rqst_id} of trace {trace_id}: {verdict_row[0]}\n"
                f"  not explained: the property's oracle failed ({error}); fix its template, then analyze again")

    def _items(self, key: Key, prop: Property, pairs: list[dict], requests: dict,
               oks: dict) -> list[tuple]:
        trace_id, rqst_id = key[0], key[2]
        rows = []
        for pair in pairs:
            if prop.type == "PC":
                found = sorted(oks.get((trace_id, pair["item"]), []))
                what, events = f"q {pair['item']}", "ok at " + (", ".join(map(_seconds, found)) or "never")
            elif pair["item"] is None:  # a verdict no y request decided (x interrupted by nothing of y)
                what, events = "no y request", "the trace holds no request of y"
            elif pair["item"] == DEADLINE_ITEM:  # not C's: whether the end came by the deadline, in words
                what, events = "deadline", pair["detail"]
            elif pair["item"] == SPAN_ITEM:  # IN's C holds inside the span, OUT's outside
                inside = pair["conflicts"] == (prop.type == "OUT")
                what, events = "state", ("inside" if inside else "outside") + " the span an ok of q enters, an ok of y leaves"
            elif pair["item"].startswith(ARGUMENT_ITEM):  # a value-domain oracle's argument of x(i)
                service, *_, args = requests[(trace_id, rqst_id)]
                name = pair["item"][len(ARGUMENT_ITEM):]
                given = json.loads(args) if args else {}
                what = f"argument {name}"
                events = (json.dumps(given[name]) if name in given else "missing") + \
                    f"; domain {self.interface.services[service].args[name].describe()}"
            else:
                service, t, final_t, reply, cls, _ = requests[(trace_id, int(pair["item"]))]
                what = f"y {service} #{pair['item']}"
                events = f"{self._instants((trace_id, int(pair['item'])), t, '')}, {reply or 'no final'} " \
                    f"({cls or '-'}) at {_seconds(final_t)}"
            shift = None if pair["shift"] == float("inf") else pair["shift"]
            # the distance whose order is not sure (rule 7): a pair may say an order is sure whatever its shift
            movable = pair.get("movable", pair["shift"])
            # a deadline's distance is to an instant of the bench's own clock: only the transport blurs it
            epsilon = self._epsilon(trace_id)[2 if pair["item"] == DEADLINE_ITEM else 0]
            near = movable is not None and movable != float("inf") and round(movable, 6) < epsilon
            rows.append((*([pair["part"]] if "part" in pair else []), what, events,
                         "yes" if pair["conflicts"] else "no", "yes" if pair["conflict_rejected"] else "no",
                         shift, "yes" if near else "no"))
        return rows

    def _epsilon(self, trace_id: int) -> tuple[float, str, float]:
        """The epsilon the trace was judged with, where it comes from, and the transport's (view trace_epsilon)."""
        return self.trace_epsilon.get(trace_id, (self.epsilon, "analysis", self.epsilon))

    def _instants(self, request: tuple[int, int], t: float, at: str, unit: str = "") -> str:
        """When a request was sent, and taken where the SUT replied `taken` to it (its instant `t`
        is then that reply's): "sent at 1.0 s, taken at 1.2 s"."""
        if request not in self.sent:
            return f"sent{at} {_seconds(t)}{unit}"
        return f"sent{at} {_seconds(self.sent[request])}{unit}, taken{at} {_seconds(t)}{unit}"

    def _epsilon_text(self, trace_id: int) -> str:
        epsilon, source, transport = self._epsilon(trace_id)
        deadlines = f"; deadlines {transport:g} s, the transport's" if transport != epsilon else ""
        return f" (epsilon {epsilon:g} s{EPSILON_SOURCES.get(source, '')}{deadlines})"

    def _text(self, key: Key, verdict_row: tuple, requests: dict, oks: dict, pairs: list[dict]) -> str:
        trace_id, property_id, rqst_id = key
        verdict, c_holds, margin, suspicious = verdict_row
        prop = self.properties[property_id]
        service, t, final_t, reply, cls, args = requests[(trace_id, rqst_id)]
        undefined = "no goal to cancel" if prop.type == "CAN" else "x(i) was rejected"
        condition = {True: "true", False: "false", None: f"undefined ({undefined})"}[c_holds]
        lines = [f"{property_id} on request {rqst_id} of trace {trace_id}: {verdict}",
                 f"  x(i) {service}{f' {args}' if args and args != '{}' else ''} "
                 f"{self._instants((trace_id, rqst_id), t, ' at', ' s')}; final reply "
                 + (f"{reply} (class {cls or 'not in the catalogue'}) at {_seconds(final_t)} s" if reply else "none"),
                 f"  C is {condition}; margin {_seconds(margin)} s; "
                 + ("suspicious" if suspicious else "not suspicious") + self._epsilon_text(trace_id)]
        rows = self._items(key, prop, pairs, requests, oks)
        if rows:
            head = (["part"] if "part" in pairs[0] else []) + ["item", "events", "makes C false", "rejected",
                                                               "shift s", "near"]
            lines.append("  " + format_table(head, rows, null="never").replace("\n", "\n  "))
        else:
            lines.append("  nothing in the trace could make C false")
        if c_holds is False:
            lines.append(f"  C would hold only if every item that makes it false moved by its shift "
                         f"(the largest: {_seconds(margin)} s).")
        elif c_holds:
            lines.append(f"  C would fail if one item moved by its shift (the smallest: {_seconds(margin)} s).")
        if any(p.get("caused") for p in pairs):
            lines.append("  Every request that may have ended x(i) makes C false: one of them came before "
                         "the end whatever the observed order, so C cannot hold.")
        return "\n".join(lines)


def explanations(con, verdicts: list[dict]) -> dict[Key, str]:
    """For the report: the explanations of these verdict rows. Without the properties the verdicts
    were made from (their files moved away), it explains nothing."""
    try:
        explainer = Explainer(con, *judged_properties(con))
    except UntimelyError:
        return {}
    return explainer.explain([(v["trace_id"], v["property_id"], v["rqst_id"]) for v in verdicts])


def main(db: str, trace_id: int, property: str, rqst_id: int | None = None) -> int:
    con = connect(db, read_only=True)
    require_analysis(con, db, ("verdicts",), "verdicts to explain")
    interface, properties = judged_properties(con)
    if property not in properties:
        raise StoreError(f"no property {property!r} in the properties the verdicts were made from; "
                         f"use one of: {', '.join(properties)}")
    requests = analysis_reads.judged_requests(con, trace_id, property)
    if rqst_id is not None:
        if rqst_id not in requests:
            raise StoreError(f"trace {trace_id} has no verdict of {property} on request {rqst_id}; "
                             f"it has verdicts on requests {requests or 'none'}")
        requests = [rqst_id]
    if not requests:
        raise StoreError(f"trace {trace_id} has no verdict of {property}; list its verdicts with "
                         f"python -m harness sql \"select * from verdicts where trace_id = {trace_id}\"")
    texts = Explainer(con, interface, properties).explain([(trace_id, property, r) for r in requests])
    print("\n\n".join(texts.values()))
    return 0
