{#- The one definition of a bad trace (paper Table II): it hung, crashed, or holds at least one FN
    or FP verdict. A trace that is not bad but holds an `unknown` verdict (an oracle failed) is
    `unknown`: neither good nor bad, as Jepsen's checkers rank :unknown between false and true, so
    a failed oracle never reads as robust. One row per trace Tables II-IV count (trace_scope), with its verdict counts, and
    what its verdicts' alternatives allow (view verdict_options): `_min` whatever the order of the
    events closer than epsilon was, `_max` in some order.
    `temp`: a temporary view, for a store analysed before this view existed and read as it is;
    `alternatives`: what stands for the column in such a store, which predates it ('[]'). -#}
{%- set alternatives = alternatives | default('alternatives') %}
create or replace {{ 'temp ' if temp | default(false) }}view trace_badness as
with counted as (
    select t.trace_id, t.sut, t.outcome, t.script_id
    from traces t semi join (select trace_id from trace_scope where counted) using (trace_id)
),
tallied as (
    select trace_id,
           count(*) filter (where verdict = 'FN') as fn,
           count(*) filter (where verdict = 'FP') as fp,
           count(*) filter (where verdict = 'TP') as tp,
           count(*) filter (where verdict = 'unknown') as unknown,
           count(*) filter (where suspicious and verdict in ('FN', 'FP')) as suspicious,
           bool_or(must_be(verdict, {{ alternatives }}, ['FN'])) as fn_min,
           bool_or(can_be(verdict, {{ alternatives }}, ['FN'])) as fn_max,
           bool_or(must_be(verdict, {{ alternatives }}, ['FP'])) as fp_min,
           bool_or(can_be(verdict, {{ alternatives }}, ['FP'])) as fp_max,
           bool_or(must_be(verdict, {{ alternatives }}, ['FN', 'FP'])) as fn_or_fp_min
    from verdicts
    group by trace_id
),
judged as (
    select c.*, coalesce(v.fn, 0) as fn, coalesce(v.fp, 0) as fp, coalesce(v.tp, 0) as tp,
           coalesce(v.suspicious, 0) as suspicious, coalesce(v.unknown, 0) > 0 as with_unknown,
           c.outcome = 'hung' as hung, c.outcome = 'crashed' as crashed,
           coalesce(v.fn, 0) > 0 as with_fn, coalesce(v.fp, 0) > 0 as with_fp,
           coalesce(v.fn_min, false) as with_fn_min, coalesce(v.fn_max, false) as with_fn_max,
           coalesce(v.fp_min, false) as with_fp_min, coalesce(v.fp_max, false) as with_fp_max,
           coalesce(v.fn_or_fp_min, false) as fn_or_fp_min
    from counted c left join tallied v using (trace_id)
),
flagged as (
    select * exclude (fn_or_fp_min), hung or crashed or with_fn or with_fp as bad,
           hung or crashed or fn_or_fp_min as bad_min,
           hung or crashed or with_fn_max or with_fp_max as bad_max
    from judged
)
-- unknown_min: unknown in every order of the events closer than epsilon (bad in none);
-- unknown_max: in some order (not bad in every one)
select * exclude (with_unknown), with_unknown and not bad as unknown,
       with_unknown and not bad_max as unknown_min, with_unknown and not bad_min as unknown_max
from flagged
