-- What the last analysis changed (verdicts_previous holds the verdicts of the analysis before
-- it): per variant, property, previous verdict and new verdict, how many verdict rows moved.
-- A row that only one analysis has shows NULL on the other side.
create or replace view verdict_transitions as
with paired as (
    select trace_id, property_id, coalesce(c.family, p.family) as family,
           p.verdict as previous, c.verdict as current
    from verdicts_previous p full join verdicts c using (trace_id, property_id, rqst_id, module, service)
)
select t.sut, property_id, family, previous, current, count(*) as verdicts
from paired join traces t using (trace_id)
where previous is distinct from current
group by all
