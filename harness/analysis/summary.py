"""What `analyze` prints after judging (and `campaign` at its end): the paper's Tables II-IV from the
views, which traces they leave out, the epsilons, the flag's accuracy on the ground truth, the
interface latency of real-time runs and the least covered properties."""
from __future__ import annotations

import duckdb

from harness.store import analysis_reads
from harness.store.analysis_reads import family_order
from harness.store.reads import ordered
from harness.store.record import CampaignRecord, records
from harness.textable import counted, format_table, percent, rate_interval, with_orders


def _rates_by_family(con, view: str, column: str, suts: list[str]) -> str:
    """Paper layout: one row per family (properties-file order, then All), one column per variant;
    each cell the rate, its 95% Wilson interval and n, then o= its interval over the orders of events."""
    cells = {(sut, family): with_orders(rate_interval(*values), lowest, highest)
             for sut, family, lowest, highest, *values in
             analysis_reads.rate_cells(con, view, column)}
    return format_table(["family"] + suts,
                        [[f] + [cells.get((s, f), "-") for s in suts] for f in family_order(con)])


def flag_accuracy(con) -> tuple[int, int, int, int]:
    """Over the requests judged on both timelines: (verdicts, inverted verdicts, inverted and
    flagged, flagged). Recall = inverted and flagged / inverted; precision = inverted and flagged / flagged."""
    judged, flagged = analysis_reads.judged_both_ways(con)
    inverted, caught = analysis_reads.inverted(con)
    return judged, inverted, caught, flagged


def analysis_summary(con: duckdb.DuckDBPyConnection, epsilon: float) -> str:
    cursor = con.execute(ordered(con, "trace_robustness"))
    columns, robustness = [d[0] for d in cursor.description], cursor.fetchall()
    suts = [r[0] for r in robustness]
    rates = [i for i, c in enumerate(columns) if c.startswith("t_rob")]
    table2 = format_table(columns, [tuple(percent(v) + "%" if i in rates else v for i, v in enumerate(r))
                                    for r in robustness])
    parts = ["Table II - per trace results\n" + table2,
             "Table III - true positive rates TP/(TP+FN), % [95% Wilson interval] n=TP+FN "
             "o=[lowest, highest] over the orders of events closer than epsilon\n"
             + _rates_by_family(con, "tp_rates", "tp_rate", suts),
             "Table IV - false positive rates FP/(FP+TN), % [95% Wilson interval] n=FP+TN "
             "o=[lowest, highest] over the orders of events closer than epsilon\n"
             + _rates_by_family(con, "fp_rates", "fp_rate", suts)]
    left_out = analysis_reads.left_out(con)
    if left_out:
        parts.append("Not counted in Tables II-IV (view trace_scope): "
                     + "; ".join(f"{n} trace{'s' * (n != 1)}: {why}" for why, n in left_out) + ".")
    parts.append(epsilons(con))
    judged, inverted, caught, flagged = flag_accuracy(con)
    if judged:
        recall = f"recall {percent(caught / inverted)}%" if inverted else "no recall to measure"
        precision = f"precision {percent(caught / flagged)}%" if flagged else "no precision to measure"
        parts.append(f"Ground truth: {inverted} of {judged} observed verdicts differ from the verdicts "
                     f"on the internal timeline (view inversions). The suspicious flag (epsilon {epsilon:g} s) "
                     f"caught {caught} of them ({recall}) and is raised on {counted(flagged, 'verdict')} in all "
                     f"({precision}). The SUT's internal events "
                     f"settle all {flagged} uncertain verdicts: {caught} change, {flagged - caught} hold.")
    cursor = analysis_reads.interface_latency(con)
    latency = cursor.fetchall()
    if latency:
        parts.append("Interface latency of the real-time runs (ping round trips, wall s; "
                     "suggested epsilon in mission s)\n" + format_table([d[0] for d in cursor.description], latency))
    parts.append(least_covered(con))
    return "\n\n".join(parts)


def epsilons(con) -> str:
    """Which epsilon the traces were judged with (view trace_epsilon): the analysis's, per
    real-time trace the one its pings measured, or 0 for another trace whose SUT told its order."""
    found = analysis_reads.epsilon_sources(con)
    said = []
    for source, n, low, high in found:
        value = f"{low:g} s" if low == high else f"{low:g} to {high:g} s"
        said.append(f"{value} for {n} trace{'s' * (n != 1)} "
                    + {"analysis": "(the analysis's --epsilon)", "taken": "(the SUT replied taken to every request: "
                       "it told its order)"}.get(source, "(measured by the pings of each real-time run)"))
    return "Epsilon (view trace_epsilon): " + "; ".join(said) + "."


def least_covered(con: duckdb.DuckDBPyConnection, shown: int = 5) -> str:
    """The properties whose condition was false on the fewest requests, on their worst variant
    (of equally bad ones, the first by name); targeted mutants are suggested unless they made them."""
    found = analysis_reads.least_covered(con, shown)
    listed = ", ".join(f"{p} {n} ({sut})" for p, n, sut in found)
    targeted = any(r.strategy == "targeted" for _, _, r in records(con, CampaignRecord))
    more = ("More cases: more --mutants, or another --seed, of the targeted campaign" if targeted
            else "More cases: python -m harness campaign --strategy targeted")
    return f"Least covered (requests with C false, on the variant with fewest; view coverage): {listed}. {more}"
