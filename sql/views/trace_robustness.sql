-- Paper Table II, one row per variant: how many counted traces are bad (view trace_badness) and
-- why; t_rob is the fraction of good traces. The _certain columns count only certain FN and FP
-- verdicts: t_rob_certain is t_rob if every possible one were a false observation.
create or replace view trace_robustness as
select sut, count(*) as total,
       count(*) filter (where hung) as hung,
       count(*) filter (where crashed) as crashed,
       count(*) filter (where with_fn) as with_fn,
       count(*) filter (where with_fp) as with_fp,
       count(*) filter (where bad) as bad,
       count(*) filter (where not bad) / count(*) as t_rob,
       count(*) filter (where with_fn_certain) as with_fn_certain,
       count(*) filter (where with_fp_certain) as with_fp_certain,
       count(*) filter (where bad_certain) as bad_certain,
       count(*) filter (where not bad_certain) / count(*) as t_rob_certain
from trace_badness
group by sut
