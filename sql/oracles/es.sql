{#- ES[x, y], excluded start: C false iff some y(j) requested before x(i) is still ongoing at
    x(i) (its final reply comes after x(i), or never). Same verdict table as PC; 'na' when
    every y(j) that makes C false was itself rejected. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro ctes(name, x, y, r_p) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
-- each x(i) with every other y(j) of its trace, placed relative to x(i)
{{ name }}_met as (
    select x.trace_id, x.rqst_id, x.t, y.rqst_id as y_rqst_id, y.t as y_t, y.final_t as y_final_t, y.class as y_class,
           {{ base.before('y.', 'x.') }} as y_first,
           coalesce({{ base.before('y.final_', 'x.') }}, false) as y_ended
    from {{ name }}_x x
    left join {{ name }}_y y on y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id
),
-- y(j) conflicts if sent before x(i) and not ended before it; its shift is how far its request
-- or its final reply would have to move to the other side of x(i)
{{ name }}_pairs as (
    select trace_id, rqst_id, y_rqst_id::varchar as item,
           y_first and not y_ended as conflicts,
           case when y_first and not y_ended then least(t - y_t, y_final_t - t)
                when y_ended then t - y_final_t
                else y_t - t end as shift,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met
),
{{ judge.condition(name) }},
{{ judge.judged(name, r_p, ['T', 'Z']) }}
{%- endmacro %}
