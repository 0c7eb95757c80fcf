{#- ES[x, y], excluded start: C false iff some y(j) requested before x(i) is still ongoing at
    x(i) (its final reply comes after x(i), or never). Same verdict table as PC; 'na' when
    every y(j) that makes C false was itself rejected. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_parameters.sql' as parameters %}
{% import 'oracles/_causes_per_property.sql' as causes with context %}

{% macro ctes(name, x, y, r_p) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'y': y, 'r_p': r_p}]) }},
{{ one_pass(name, (x + y) | modules) }}
{%- endmacro %}

{#- Every ES property at once, from the parameter table `name`_properties and _services; `modules`
    (one property's, without the analysis's shared causes): see _causes_per_property.sql.
    `mutual`: ES[x, y] judged with ES[y, x] under the same r_P (mx_r.sql), so a y(j) rejected with
    r_P says an x ran when the layer took it (rule 8). -#}
{% macro one_pass(name, modules=none, mutual=false) -%}
{{ parameters.relevant(name, 'x') }},
{{ parameters.relevant(name, 'y') }},
{{ causes.keyed(name, [name ~ '_x', name ~ '_y'], modules) }},
-- rule 8: a y(j) rejected with r_P by a mutual exclusion was taken while an x ran; when a single
-- x(i) could have run then (not rejected, sent before y(j)'s rejection was observed, its own final
-- reply not observed before y(j) was sent), x(i) was taken before y(j)
{{ name }}_named as (
{% if mutual %}
    select y.property_id, y.trace_id, y.rqst_id as y_rqst_id, any_value(x.rqst_id) as rqst_id
    from {{ name }}_y y
    join {{ name }}_x x on x.property_id = y.property_id and x.trace_id = y.trace_id and x.rqst_id <> y.rqst_id
         and x.class is distinct from 'R'
         and {{ base.before('x.', 'y.final_') }} and not coalesce({{ base.before('x.final_', 'y.') }}, false)
    where y.class = 'R' and y.reply = y.r_p
    group by y.property_id, y.trace_id, y.rqst_id having count(*) = 1
{% else %}
    select null::integer as property_id, null::integer as trace_id, null::integer as y_rqst_id,
           null::integer as rqst_id where false
{% endif %}
),
-- each x(i) and y(j) with the sole cause of its end, if any (_causes.sql), and the x(i) a y(j)
-- named (rule 8); looked up per request rather than per pair, which are many more
{{ name }}_xs as (
    select x.*, s.cause_id as sole_cause
    from {{ name }}_x x left join {{ name }}_sole s using (property_id, trace_id, rqst_id)
),
{{ name }}_ys as (
    select y.*, s.cause_id as sole_cause, n.rqst_id as named, y.final_t is null and {{ judge.ended_first('y.trace_id') }} as untaken
    from {{ name }}_y y left join {{ name }}_sole s using (property_id, trace_id, rqst_id)
    left join {{ name }}_named n on n.property_id = y.property_id and n.trace_id = y.trace_id and n.y_rqst_id = y.rqst_id
),
-- each x(i) with every other y(j) of its trace, placed relative to x(i); whether y(j) is the
-- sole cause of x(i)'s end, or x(i) of y(j)'s, or named x(i)
{{ name }}_met as (
    select x.property_id, x.trace_id, x.rqst_id, x.t, y.rqst_id as y_rqst_id, y.t as y_t, y.final_t as y_final_t, y.class as y_class,
           {{ base.before('y.', 'x.') }} as y_first,
           coalesce({{ base.before('y.final_', 'x.') }}, false) as y_ended,
           coalesce(x.sole_cause = y.rqst_id, false) as y_ended_x, coalesce(y.sole_cause = x.rqst_id, false) as x_ended_y,
           coalesce(y.named = x.rqst_id, false) as y_named_x,
           y.untaken as y_untaken
    from {{ name }}_xs x
    join {{ name }}_ys y on y.property_id = x.property_id and y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id  -- an x(i) without y(j) has no pair
),
-- y(j) conflicts if sent before x(i) and not ended before it; its shift is how far its request
-- or its final reply would have to move to the other side of x(i). `movable`: the same unless
-- the order is sure (rule 7): a y(j) whose reply was observed before x(i) was sent, a y(j) that
-- x(i) ended as its sole cause (x(i) came while it ran), one that ended x(i) or that named x(i)
-- in its rejection (it came after)
{{ name }}_pairs as (
    select property_id, trace_id, rqst_id, y_rqst_id::varchar as item,
           y_first and not y_ended as conflicts,
           case when y_first and not y_ended then least(t - y_t, y_final_t - t)
                when y_ended then t - y_final_t
                else y_t - t end as shift,
           case when y_first and not y_ended and y_untaken then 0  -- it may never have been taken
                when y_first and not y_ended then (case when x_ended_y then 'infinity'::double else least(t - y_t, y_final_t - t) end)
                when y_ended then 'infinity'::double
                when y_ended_x or y_named_x then 'infinity'::double
                else y_t - t end as movable,
           y_untaken as untaken,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met
),
{{ judge.condition(name, movable='p.movable', untaken='untaken', keyed=true) }},
{{ judge.judged(name, 'r_p', ['T', 'Z'], keyed=true) }}
{%- endmacro %}
