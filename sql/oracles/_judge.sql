{#- Judging a property's pairs (see _base.sql): its condition C per request, its verdict by
    the verdict table, and whether reordering events closer than `epsilon` could change that
    verdict (`suspicious`, docs/analyzer.md). Epsilon is the trace's (CTE `epsilons`, see
    _epsilon.sql), else `epsilon` from the context: import this file `with context`. -#}

{% macro near(seconds, trace_epsilon='e.epsilon') -%}
coalesce(round({{ seconds }}, 6) < coalesce({{ trace_epsilon }}, {{ epsilon }}), false)
{%- endmacro %}

{% macro ended_first(trace_id='trace_id') -%}
-- the trace ended before every message reached its end (hung, crashed): a request without a reply may
-- never have been taken, and a reply may have been lost on its way
{{ trace_id }} in (select trace_id from traces where outcome <> 'completed')
{%- endmacro %}

{#- `keyed`: the pairs and requests are a one-pass oracle's (_parameters.sql), each row of one
    property (`property_id`), whose code is the column `code` of its requests. -#}
{% macro key(keyed) %}{{ 'property_id, ' if keyed }}trace_id, rqst_id{% endmacro %}

{% macro condition(name, defined='true', caused='false', movable='p.shift', untaken='false', keyed=false) -%}
-- C per request: false iff some pair conflicts. To flip C, every conflict would have to go
-- (the largest conflicting shift) or any one non-conflict would have to start (the smallest).
-- A pair is `near` when its shift is below epsilon, both rounded to microseconds (a 10 ms gap
-- is never on either side of 10 ms by float rounding); the order of the others is sure.
-- `caused`: a pair that says C is false with a conflict that was not rejected (x(i)'s end had a
-- cause, see ee.sql). `movable`: the distance of the pair's events whose order is not sure (a
-- template's pairs may say, rule 7, that an order is sure whatever its shift: 'infinity').
-- `untaken`: a conflict whose taking is unknown (rule 10): it may also have been rejected.
{{ name }}_agg as (
    select {{ key(keyed) }},
           bool_or(conflicts) as any_conflict,
           coalesce(bool_and(conflict_rejected) filter (where conflicts), false) as conflicts_rejected,
           case when bool_or(conflicts) then max(shift) filter (where conflicts)
                else min(shift) filter (where not conflicts) end as margin_s,
           -- the conditions that reordering the near pairs could give: C true, C false with
           -- every conflict rejected (na), C false with a conflict that was not rejected
           not coalesce(bool_or(conflicts and not near or {{ caused }}), false) as may_hold,
           coalesce(bool_and(conflict_rejected) filter (where conflicts and not near), true)
               and coalesce(bool_or((conflicts or near) and (conflict_rejected or {{ untaken }})), false)
               and not coalesce(bool_or({{ caused }}), false) as may_be_na,
           coalesce(bool_or((conflicts or near) and not conflict_rejected), false) as may_fail
    from (select p.*, {{ near(movable) }} as near from {{ name }}_pairs p left join epsilons e using (trace_id))
    group by {{ key(keyed) }}
),
{{ name }}_cond as (
    select {{ 'x.property_id, x.r_p, x.z_p, ' if keyed }}x.trace_id, x.rqst_id, x.module, x.service, x.reply, x.class,
           case when {{ defined }} then not coalesce(a.any_conflict, false) end as c_holds,
           coalesce(a.conflicts_rejected, false) as conflicts_rejected, a.margin_s,
           coalesce(a.may_hold, true) as may_hold, coalesce(a.may_be_na, false) as may_be_na,
           coalesce(a.may_fail, false) as may_fail
    from {{ name }}_x x left join {{ name }}_agg a using ({{ key(keyed) }})
)
{%- endmacro %}

{% macro verdict(c_holds, na, code, accepted, keyed=false) -%}
case when reply is null then 'omega'
     when {{ c_holds }} is null then 'op'
     when not {{ c_holds }} and {{ na }} then 'na'
     when reply = {{ code if keyed else code | lit }} then (case when {{ c_holds }} then 'FP' else 'TP' end)
     when class in ({{ accepted | map('lit') | join(', ') }}) then (case when {{ c_holds }} then 'TN' else 'FN' end)
     else 'op' end
{%- endmacro %}

{% macro undefined_alternatives(code, accepted, keyed) -%}
list_sort(list_distinct(list_filter([{{ verdict('true', 'false', code, accepted, keyed) }},
                                     {{ verdict('false', 'false', code, accepted, keyed) }}],
                                    lambda other: other <> verdict)))
{%- endmacro %}

{% macro judged(name, code, accepted, keyed=false, undefined_settles=false) -%}
-- the verdict table: `code` is the property's own rejection or interruption code, `accepted`
-- the reply classes that mean the activity ran; c_holds NULL = C undefined for this request.
-- alternatives: the other verdicts that the conditions reordering the near pairs could give
-- would make, sorted; none: the verdict is certain. A rejection with the property's own code is
-- the layer's account that C was false when it took x(i): C true is no alternative for it. No
-- final reply in a trace that ended first: the reply may have been lost, any reply in any
-- reachable condition is an alternative (the property's code, an accepted one, another one).
-- `undefined_settles`: C undefined (op) because the order of two requests cannot be observed (a
-- state change pending at x(i)); either order may be the layer's, so the verdicts C true and C
-- false give are its alternatives: a rejection with the code is TP or FP, an accepted x TN or FN.
{{ name }}_verdict as (
    select *, {{ verdict('c_holds', 'conflicts_rejected', code, accepted, keyed) }} as verdict
    from {{ name }}_cond
),
{{ name }}_judged as (
    select {{ key(keyed) }}, module, service, reply, c_holds, verdict,
           case when c_holds is not null then nullif(margin_s, 'infinity') end as margin_s,
           case when c_holds is null then {{ undefined_alternatives(code, accepted, keyed) if undefined_settles
                                              else '[]::varchar[]' }}
                -- most requests can reach their observed condition alone: no alternative, and
                -- no lists built for them
                when reply is not null and not may_be_na and (c_holds and may_hold and not may_fail
                     or not c_holds and not conflicts_rejected and may_fail and not may_hold) then []::varchar[]
                else list_sort(list_distinct(list_filter([
                    case when may_hold and not (reply = {{ code if keyed else code | lit }} and class = 'R')
                         then {{ verdict('true', 'false', code, accepted, keyed) }} end,
                    case when may_be_na then {{ verdict('false', 'true', code, accepted, keyed) }} end,
                    case when may_fail then {{ verdict('false', 'false', code, accepted, keyed) }} end]
                    || case when reply is null and {{ ended_first() }} then
                           (case when may_hold then ['FP', 'TN', 'op'] else [] end)
                           || (case when may_be_na then ['na'] else [] end)
                           || (case when may_fail then ['TP', 'FN', 'op'] else [] end)
                       else [] end,
                    lambda other: other is not null and other <> verdict))) end as alternatives
    from {{ name }}_verdict
)
{%- endmacro %}
