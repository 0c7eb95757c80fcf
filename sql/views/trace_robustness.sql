-- Paper Table II, one row per variant: how many counted traces are bad (view trace_badness) and
-- why; t_rob is the fraction of good traces.
create or replace view trace_robustness as
select sut, count(*) as total,
       count(*) filter (where hung) as hung,
       count(*) filter (where crashed) as crashed,
       count(*) filter (where with_fn) as with_fn,
       count(*) filter (where with_fp) as with_fp,
       count(*) filter (where bad) as bad,
       count(*) filter (where not bad) / count(*) as t_rob
from trace_badness
group by sut
