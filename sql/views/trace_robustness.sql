-- Paper Table II, one row per variant: how many counted traces are bad (view trace_badness) and
-- why; t_rob is the fraction of good traces. Each count has its interval over the orders of the
-- events closer than epsilon (_min, _max: each trace is bad or not on its own verdicts, so the
-- extremes are the sums of each trace's), and t_rob its interval [t_rob_min, t_rob_max].
create or replace view trace_robustness as
select sut, count(*) as total,
       count(*) filter (where hung) as hung,
       count(*) filter (where crashed) as crashed,
       count(*) filter (where with_fn) as with_fn,
       count(*) filter (where with_fp) as with_fp,
       count(*) filter (where bad) as bad,
       count(*) filter (where not bad) / count(*) as t_rob,
       count(*) filter (where with_fn_min) as with_fn_min,
       count(*) filter (where with_fn_max) as with_fn_max,
       count(*) filter (where with_fp_min) as with_fp_min,
       count(*) filter (where with_fp_max) as with_fp_max,
       count(*) filter (where bad_min) as bad_min,
       count(*) filter (where bad_max) as bad_max,
       count(*) filter (where not bad_max) / count(*) as t_rob_min,
       count(*) filter (where not bad_min) / count(*) as t_rob_max
from trace_badness
group by sut
