"""`python -m harness diff`: what the last analysis changed (docs/reference/commands.md).

`analyze` keeps the verdicts and Tables II-IV of the analysis it replaces (verdicts_previous,
table_values_previous); the views verdict_transitions and table_changes compare them with the
new ones. This module prints both, after `analyze` and at any time with `diff`.
"""
from __future__ import annotations

from harness.store.analysis_reads import last_analyses
from harness.store.reads import analyses_made, ordered, require_analysis
from harness.store.database import connect
from harness.textable import counted, format_table, percent

RATES = ("t_rob", "tp_rate", "fp_rate")  # the measures shown as percentages; the others are counts


def _value(measure: str, value):
    return percent(value) if measure in RATES else (None if value is None else int(value))


def changes(con) -> str:
    """The verdict transitions and the changed cells of Tables II-IV, as text."""
    if analyses_made(con) < 2:
        return "Changes: this is the first analysis of the store; there is nothing to compare it with."
    analyses = last_analyses(con)
    now = analyses[0]
    before = (f"analysis {analyses[1][0]} of {analyses[1][1]:%Y-%m-%d %H:%M:%S}, epsilon {analyses[1][2]:g} s"
              if len(analyses) > 1 else "the analysis before it")
    head = f"Changes made by analysis {now[0]} (epsilon {now[2]:g} s) to the verdicts of {before}"
    cursor = con.execute(ordered(con, "verdict_transitions"))
    transitions = cursor.fetchall()
    if not transitions:
        return head + ": none, every verdict is the same."
    moved = sum(r[-1] for r in transitions)
    parts = [f"{head}: {counted(moved, 'verdict')} changed.",
             "Verdict transitions (NULL: no such row in that analysis)\n"
             + format_table([d[0] for d in cursor.description], transitions)]
    cursor = con.execute(ordered(con, "table_changes"))
    cells = sorted(cursor.fetchall(), key=lambda r: ("II", "III", "IV").index(r[2]))
    if cells:
        parts.append("Tables II-IV: changed cells (rates in %)\n" + format_table(
            ["table", "sut", "family", "measure", "previous", "current"],
            [(t, sut, family, m, _value(m, p), _value(m, c)) for sut, family, t, m, p, c in cells], null="-"))
    return "\n\n".join(parts)


def main(db: str) -> int:
    con = connect(db, read_only=True)
    require_analysis(con, db, ("verdict_transitions", "table_changes"), "analysis to compare")
    print(changes(con))
    return 0
