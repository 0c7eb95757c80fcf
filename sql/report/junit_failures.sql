-- What fails a JUnit test case of `analyze --junit`: every FN and FP verdict of a counted trace,
-- and every counted hung or crashed trace (property_id null), with the reproducer shrunk from
-- that behaviour when there is one (shrink, campaign --shrink). `certain`: false for a verdict that
-- some order of the events closer than epsilon would change (an outcome is certain).
with verdict_failures as (
    select t.sut, v.property_id, v.trace_id, v.rqst_id, v.verdict as failure, null as error, v.certain
    from verdicts v join trace_scope t using (trace_id)
    where t.counted and v.verdict in ('FN', 'FP')
),
outcome_failures as (
    select t.sut, null as property_id, t.trace_id, null as rqst_id, tr.outcome as failure, tr.error, true
    from trace_scope t join traces tr using (trace_id)
    where t.counted and tr.outcome in ('hung', 'crashed')
),
failures as (
    select * from verdict_failures
    union all
    select * from outcome_failures
),
reproducers as (
    select sut, property_id, verdict, min(script_id) as script_id, arg_min(body, script_id) as body
    from (
{% include "report/shrunk_reproducers.sql" %}
    )
    group by all
)
select f.sut, f.property_id, f.trace_id, f.rqst_id, f.failure, f.error, f.certain,
       r.script_id as reproducer, r.body
from failures f
left join reproducers r
    on r.sut = f.sut and r.verdict = f.failure and r.property_id is not distinct from f.property_id
order by f.sut, f.property_id nulls first, f.trace_id, f.rqst_id
