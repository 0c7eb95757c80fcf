-- Paper Table II, one row per variant: a trace is bad if it hung, crashed, or holds at least
-- one FN or FP verdict; t_rob is the fraction of good traces. Only counted traces (trace_scope).
create or replace view trace_robustness as
with flagged as (
    select trace_id, bool_or(verdict = 'FN') as with_fn, bool_or(verdict = 'FP') as with_fp
    from verdicts where verdict in ('FN', 'FP')
    group by trace_id
),
judged as (
    select t.sut, t.outcome = 'hung' as hung, t.outcome = 'crashed' as crashed,
           coalesce(f.with_fn, false) as with_fn, coalesce(f.with_fp, false) as with_fp
    from traces t semi join (select trace_id from trace_scope where counted) using (trace_id)
    left join flagged f using (trace_id)
),
bad as (
    select *, hung or crashed or with_fn or with_fp as bad from judged
)
select sut, count(*) as total,
       count(*) filter (where hung) as hung,
       count(*) filter (where crashed) as crashed,
       count(*) filter (where with_fn) as with_fn,
       count(*) filter (where with_fp) as with_fp,
       count(*) filter (where bad) as bad,
       count(*) filter (where not bad) / count(*) as t_rob
from bad
group by sut
