-- What was found, per variant (issue 21): each (property, kind) that went wrong -- FN, FP, hung,
-- crashed (property null) -- with the first trace that showed it, how many traces show it, and
-- its shrunk reproducer if one was made (the first shrunk script recorded for it).
{% import 'report/_shrinks.sql' as shrinks %}
create or replace {{ 'temp ' if temp | default(false) }}view findings as
with found as (
    select sut, property_id, kind, min(trace_id) as first_trace, count(distinct trace_id) as traces
    from trace_findings
    group by sut, property_id, kind
),
shrink_records as (
    {{ shrinks.shrunk_scripts() }}
),
shrunk as (
    select sut, property_id, verdict as kind, min(script_id) as reproducer,
           arg_min(steps_after, script_id) as reproducer_steps
    from shrink_records
    group by all
)
select f.sut, f.property_id, f.kind, f.first_trace, f.traces, s.reproducer, s.reproducer_steps
from found f
left join shrunk s on s.sut = f.sut and s.kind = f.kind and s.property_id is not distinct from f.property_id
left join variant_positions v on v.sut = f.sut
left join property_positions p on p.property_id = f.property_id
order by v.position, p.position nulls first, f.kind
