{#- EE[x, y], excluded execution: for an accepted x(i), C false iff some y(j) is sent after
    x(i) and before its final reply (before the end of the trace if it has none).
    C true: T reply TN, z_P FP; C false: T reply FN, z_P TP; another Z code, or a rejected
    x(i) (C undefined), op; no final reply omega; 'na' when every such y(j) was rejected. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_parameters.sql' as parameters %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_causes_per_property.sql' as causes with context %}
{% set interrupts = [['x', 'y']] %}{# a y may end an x activity with z_p: causes are searched among them #}

{% macro ctes(name, x, y, z_p) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'y': y, 'z_p': z_p}]) }},
{{ one_pass(name, (x + y) | modules) }}
{%- endmacro %}

{#- Every EE property at once, from the parameter table `name`_properties and _services; `modules`
    (one property's, without the analysis's shared causes): see _causes.sql's `keyed`. -#}
{% macro one_pass(name, modules=none) -%}
{{ parameters.relevant(name, 'x') }},
{{ parameters.relevant(name, 'y') }},
{{ causes.keyed(name, [name ~ '_x', name ~ '_y'], modules) }},
-- When every candidate cause of x(i)'s end is one of its property's y, one of them stays before
-- the end whatever the observed order: C is false with a conflict that was not rejected (`caused`).
{{ name }}_caused as (
    select c.property_id, c.trace_id, c.rqst_id, bool_and(y.property_id is not null) as caused
    from {{ name }}_candidates c semi join {{ name }}_x x using (property_id, trace_id, rqst_id)
    left join {{ name }}_services y on y.property_id = c.property_id and y.role = 'y' and y.module = c.module
         and y.service = c.service
    group by c.property_id, c.trace_id, c.rqst_id
),
-- each x(i) and y(j) with the sole cause of its end, if any (_causes.sql), and whether x(i)'s
-- end was caused; looked up per request rather than per pair, which are many more
{{ name }}_xs as (
    select x.*, s.cause_id as sole_cause, c.caused
    from {{ name }}_x x left join {{ name }}_sole s using (property_id, trace_id, rqst_id)
    left join {{ name }}_caused c using (property_id, trace_id, rqst_id)
),
{{ name }}_ys as (
    select y.*, s.cause_id as sole_cause, y.final_t is null and {{ judge.ended_first('y.trace_id') }} as untaken
    from {{ name }}_y y left join {{ name }}_sole s using (property_id, trace_id, rqst_id)
),
-- each x(i) with every other y(j) of its trace, placed relative to x(i)'s activity; whether
-- y(j) is the sole cause of x(i)'s end, or x(i) of y(j)'s
{{ name }}_met as (
    select x.property_id, x.trace_id, x.rqst_id, x.t, x.final_t, x.caused, y.rqst_id as y_rqst_id, y.t as y_t, y.class as y_class,
           {{ base.before('x.', 'y.') }} as x_first,
           coalesce({{ base.before('y.', 'x.final_') }}, true) as y_before_end,
           coalesce({{ base.before('y.final_', 'x.') }}, false) as y_ended_first,
           coalesce(x.sole_cause = y.rqst_id, false) as y_ended_x, coalesce(y.sole_cause = x.rqst_id, false) as x_ended_y,
           y.untaken as y_untaken
    from {{ name }}_xs x
    join {{ name }}_ys y on y.property_id = x.property_id and y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id  -- an x(i) without y(j) has no pair
),
-- y(j) conflicts if sent while x(i) runs; its shift is how far it would have to move to the
-- other side of x(i)'s request or final reply. `movable`: the same unless the order is sure
-- (rule 7): a y(j) sent after x(i)'s reply was observed, a y(j) whose reply was observed before
-- x(i) was sent, or one that x(i) or y(j) ended as its sole cause
{{ name }}_pairs as (
    select property_id, trace_id, rqst_id, y_rqst_id::varchar as item,
           x_first and y_before_end as conflicts,
           case when x_first and y_before_end then least(y_t - t, final_t - y_t)
                when x_first then y_t - final_t
                else t - y_t end as shift,
           case when x_first and y_before_end and y_untaken then 0  -- it may never have been taken
                when x_first and y_before_end then (case when y_ended_x then 'infinity'::double else least(y_t - t, final_t - y_t) end)
                when x_first then 'infinity'::double
                when y_ended_first or x_ended_y then 'infinity'::double
                else t - y_t end as movable,
           caused,
           y_untaken as untaken,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met
),
{{ judge.condition(name, defined="class is distinct from 'R'", caused='caused', movable='p.movable',
                   untaken='untaken', keyed=true) }},
{{ judge.judged(name, 'z_p', ['T'], keyed=true) }}
{%- endmacro %}
