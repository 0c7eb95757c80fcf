{#- Table II's bad traces (view trace_badness: hung, crashed, with FN, with FP), with what lies
    behind them and their world events. -#}
{% import 'report/_behind.sql' as lists %}
with bad as (
    select trace_id, sut, outcome, script_id, fn, fp, tp, suspicious
    from trace_badness
    where bad
),
behind as (
    select b.trace_id, {{ lists.behind() }}, s.mutations
    from bad b left join verdicts v using (trace_id) left join scripts s using (script_id)
    group by b.trace_id, s.mutations
),
world as (
    select trace_id, count(*) as world_events
    from world_events semi join bad using (trace_id)
    group by trace_id
)
select b.*, h.properties, h.mutations, coalesce(w.world_events, 0) as world_events
from bad b join behind h using (trace_id) left join world w using (trace_id)
order by trace_id
