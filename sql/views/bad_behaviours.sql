-- Distinct bad behaviours (issue 10): a variant hung, or gave an FN or an FP on a property. One
-- row per behaviour with how many traces show it and a representative to shrink: the trace of
-- the shortest script (fewest characters), then the smallest trace id. Not the rule of a bad
-- trace (view trace_badness): a behaviour is per property, a crash is no behaviour to shrink, and
-- every stored trace may show one, counted in Tables II-IV or not.
create or replace view bad_behaviours as
with shown as (
    select trace_id, sut, property_id, kind as verdict
    from trace_findings
    where kind <> 'crashed'
),
sized as (
    select s.*, length(coalesce(sc.body, '')) as script_size
    from shown s join traces t using (trace_id) left join scripts sc using (script_id)
)
select sut, property_id, verdict, count(*) as traces,
       arg_min(trace_id, (script_size, trace_id)) as representative
from sized
group by sut, property_id, verdict
