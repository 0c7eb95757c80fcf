"""The ground truth against the intervals of Tables II-IV, on any judged store with internal events:
what the interval fuzz test and the campaign test check. The true figures are computed here, from
`verdicts_internal` (the oracles on the layer's own timeline), independently of the views."""
from __future__ import annotations

# Observed verdicts whose request was judged on the internal timeline too, and the internal verdict
# is neither the observed one nor among its alternatives.
MISSED = """
    select t.sut, o.trace_id, o.property_id, o.rqst_id, o.verdict, o.alternatives, i.verdict as truth
    from verdicts o join verdicts_internal i using (trace_id, property_id, module, service, rqst_id)
    join traces t using (trace_id)
    where o.verdict <> 'unknown' and i.verdict <> o.verdict and not list_contains(o.alternatives, i.verdict)
    order by all
"""
TRUE_RATES = """
    with judged as (
        select s.sut, i.family, i.verdict from verdicts_internal i join trace_scope s using (trace_id)
        where s.counted
    ),
    counted as (
        select sut, case when grouping(family) = 1 then 'All' else family end as family,
               count(*) filter (where verdict = 'TP') as tp, count(*) filter (where verdict = 'FN') as fn,
               count(*) filter (where verdict = 'FP') as fp, count(*) filter (where verdict = 'TN') as tn
        from judged group by grouping sets ((sut, family), (sut))
    )
    select sut, family, tp / nullif(tp + fn, 0) as tp_rate, fp / nullif(fp + tn, 0) as fp_rate from counted
"""
TRUE_BAD = """
    with bad as (
        select s.trace_id, s.sut, t.outcome in ('hung', 'crashed')
                   or exists (select 1 from verdicts_internal i where i.trace_id = s.trace_id
                              and i.verdict in ('FN', 'FP')) as bad
        from trace_scope s join traces t using (trace_id)
        where s.counted
    )
    select sut, count(*) filter (where bad) as bad from bad group by sut
"""


def missed(con) -> list[tuple]:
    """The verdicts whose truth their alternatives miss: (sut, trace, property, request, verdict,
    alternatives, internal verdict)."""
    return con.execute(MISSED).fetchall()


def outside(con) -> list[str]:
    """Every cell of Tables II-IV whose true figure lies outside its interval, described."""
    found = []
    bounds = {(sut, family, rate): (low, high) for rate, view in (("tp_rate", "tp_rates"), ("fp_rate", "fp_rates"))
              for sut, family, low, high in con.execute(f"select sut, family, {rate}_min, {rate}_max from {view}")
              .fetchall()}
    for sut, family, *truths in con.execute(TRUE_RATES).fetchall():
        for rate, truth in zip(("tp_rate", "fp_rate"), truths):
            low, high = bounds.get((sut, family, rate), (None, None))
            if truth is not None and (low is None or not low - 1e-12 <= truth <= high + 1e-12):
                found.append(f"{sut} {family} {rate}: truth {truth:.4f} outside [{low}, {high}]")
    table2 = dict((sut, (low, high)) for sut, low, high in
                  con.execute("select sut, bad_min, bad_max from trace_robustness").fetchall())
    for sut, bad in con.execute(TRUE_BAD).fetchall():
        low, high = table2[sut]
        if not low <= bad <= high:
            found.append(f"{sut} bad traces: truth {bad} outside [{low}, {high}]")
    return found


def cells(con) -> int:
    """How many rate cells the true figures were checked in (those with a true rate)."""
    return sum(r is not None for row in con.execute(TRUE_RATES).fetchall() for r in row[2:])
