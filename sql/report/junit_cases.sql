-- The JUnit test cases of `analyze --junit`: one per variant and property, over the traces
-- Tables II-IV count (trace_scope), with how many verdicts and how many FN and FP.
with variants as (
    select distinct sut from trace_scope where counted
),
cases as (
    select v.sut, p.family, p.property_id, p.position
    from variants v cross join properties p
)
select c.sut, c.family, c.property_id, coalesce(pv.verdicts, 0) as verdicts,
       coalesce(pv.fn, 0) as fn, coalesce(pv.fp, 0) as fp
from cases c
left join property_verdicts pv using (sut, property_id)
left join variant_positions vp using (sut)
order by vp.position, c.sut, c.position
