"""Where an analysis's time goes (bench/analyzer_bench.py): every statement `materialise` runs is
profiled by DuckDB (its `detailed` JSON profile), and its time split into planning (binding,
optimising, physical planning: serial), table scans, groupings (hash aggregates and windows), joins,
and the other operators (projections, filters, sorts, inserts), summed over the threads that ran
them; per phase of the analysis: the shared step (requests, epsilons, causes), the oracles, and
publishing the verdicts (with the views and the record). Profiling costs time of its own: the split
is of a separate analysis, in fractions beside the bench's own timed figures.
"""
from __future__ import annotations

import json
import tempfile
from collections import defaultdict
from pathlib import Path

from harness.store.database import connect

# A statement's phase, by its first words: the oracles insert their verdicts into the staged tables,
# the shared step makes temp tables; the rest publishes (written as words: this module runs no SQL).
PHASES = (("oracles", (("insert", "into", "verdicts_staged"), ("insert", "into", "verdicts_internal_staged"))),
          ("shared step", (("create", "or", "replace", "temp", "table"),)))
KINDS = (("scans", ("TABLE_SCAN", "READ_")), ("grouping", ("GROUP_BY", "WINDOW", "DISTINCT")), ("joins", ("JOIN",)))


def _phase(sql: str) -> str:
    words = tuple(sql.lower().split()[:5])
    return next((name for name, starts in PHASES if any(words[:len(start)] == start for start in starts)),
                "publishing")


def _kind(operator: str) -> str:
    return next((name for name, parts in KINDS if any(p in operator for p in parts)), "other operators")


def _operators(node: dict, into: dict) -> None:
    if node.get("type"):
        into[_kind(node["type"])] += node.get("timing") or 0.0
    for child in node.get("children", []):
        _operators(child, into)


class Profiled:
    """A connection whose every statement's profile is added to `split`: phase -> kind -> seconds."""

    def __init__(self, con, folder: Path):
        self._con, self._file = con, folder / "profile.json"
        self.split: dict[str, dict[str, float]] = defaultdict(lambda: defaultdict(float))
        self.statements: dict[str, int] = defaultdict(int)
        con.execute("set enable_profiling = 'json'")
        con.execute(f"set profiling_output = '{self._file}'")
        con.execute("set profiling_mode = 'detailed'")

    def execute(self, sql, *args):
        result = None
        for statement in self._con.extract_statements(sql) if isinstance(sql, str) else [sql]:
            result = self._con.execute(statement, *args)
            self._add(_phase(statement.query))
        return result

    def _add(self, phase: str) -> None:
        try:
            profile = json.loads(self._file.read_text())
        except (OSError, ValueError):
            return
        self.statements[phase] += 1
        self.split[phase]["planning"] += sum(profile.get(p, {}).get("total_time", 0.0)
                                             for p in ("planner", "physical_planner"))
        self.split[phase]["planning"] += sum(v for v in profile.get("optimizer", {}).values() if isinstance(v, float))
        for root in profile.get("operator", []):
            _operators(root, self.split[phase])
        self._file.unlink()

    def __getattr__(self, name):
        return getattr(self._con, name)


def time_split(path: Path, properties, threads: int, analyse) -> str:
    """The split of one analysis of the store at `path` (`analyse(con, properties)` runs it)."""
    con = connect(path)
    con.execute(f"set threads = {int(threads)}")
    with tempfile.TemporaryDirectory() as tmp:
        profiled = Profiled(con, Path(tmp))
        analyse(profiled, properties)
    con.close()
    total = sum(sum(kinds.values()) for kinds in profiled.split.values())
    lines = [f"where the time goes (DuckDB's profile of one more analysis on {threads} thread"
             f"{'s' * (threads != 1)}, operator time summed over threads: {total:.1f} s)"]
    for phase, kinds in sorted(profiled.split.items(), key=lambda item: -sum(item[1].values())):
        said = ", ".join(f"{kind} {seconds:.2f} s" for kind, seconds in sorted(kinds.items(), key=lambda kv: -kv[1]))
        lines.append(f"    {phase} ({profiled.statements[phase]} statements): {sum(kinds.values()):.2f} s = "
                     f"{sum(kinds.values()) / total:.0%}: {said}")
    return "\n".join(lines)
