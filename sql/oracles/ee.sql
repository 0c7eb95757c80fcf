{#- EE[x, y], excluded execution: for an accepted x(i), C false iff some y(j) is sent after
    x(i) and before its final reply (before the end of the trace if it has none).
    C true: T reply TN, z_P FP; C false: T reply FN, z_P TP; another Z code, or a rejected
    x(i) (C undefined), op; no final reply omega; 'na' when every such y(j) was rejected. -#}
{% import 'oracles/_base.sql' as base %}

{% macro ctes(name, x, y, z_p) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
-- each x(i) with every other y(j) of its trace, placed relative to x(i)'s activity
{{ name }}_met as (
    select x.trace_id, x.rqst_id, x.t, x.final_t, y.t as y_t, y.class as y_class,
           {{ base.before('x.', 'y.') }} as x_first,
           coalesce({{ base.before('y.', 'x.final_') }}, true) as y_before_end
    from {{ name }}_x x
    left join {{ name }}_y y on y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id
),
-- y(j) conflicts if sent while x(i) runs; its shift is how far it would have to move to the
-- other side of x(i)'s request or final reply
{{ name }}_pairs as (
    select trace_id, rqst_id,
           x_first and y_before_end as conflicts,
           case when x_first and y_before_end then least(y_t - t, final_t - y_t)
                when x_first then y_t - final_t
                else t - y_t end as shift,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met
),
{{ base.condition(name, defined="class is distinct from 'R'") }},
{{ base.judged(name, z_p, ['T']) }}
{%- endmacro %}
