{#- The one definition of a bad trace (paper Table II): it hung, crashed, or holds at least one FN
    or FP verdict; `bad_certain` counts only certain FN and FP. One row per trace Tables II-IV
    count (trace_scope), with its verdict counts.
    `temp`: a temporary view, for a store analysed before this view existed and read as it is. -#}
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
           count(*) filter (where suspicious and verdict in ('FN', 'FP')) as suspicious,
           count(*) filter (where not suspicious and verdict = 'FN') as fn_certain,
           count(*) filter (where not suspicious and verdict = 'FP') as fp_certain
    from verdicts
    group by trace_id
),
judged as (
    select c.*, coalesce(v.fn, 0) as fn, coalesce(v.fp, 0) as fp, coalesce(v.tp, 0) as tp,
           coalesce(v.suspicious, 0) as suspicious,
           c.outcome = 'hung' as hung, c.outcome = 'crashed' as crashed,
           coalesce(v.fn, 0) > 0 as with_fn, coalesce(v.fp, 0) > 0 as with_fp,
           -- counting only certain FN and FP (suspicious = not certain)
           coalesce(v.fn_certain, 0) > 0 as with_fn_certain, coalesce(v.fp_certain, 0) > 0 as with_fp_certain
    from counted c left join tallied v using (trace_id)
)
select *, hung or crashed or with_fn or with_fp as bad,
       hung or crashed or with_fn_certain or with_fp_certain as bad_certain
from judged
