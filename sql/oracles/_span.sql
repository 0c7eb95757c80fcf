{#- The state spans of IN and OUT (docs/reference/properties.md): an ok final reply of a q enters
    a span, an ok of a y leaves it, and a trace starts outside. x(i) is inside when the latest ok
    among Q and Y before it (x(i)'s own reply aside) is a q's. IN's C holds inside, OUT's outside:
    a lifecycle node serves only while active (IN), a transition is offered only in its states. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro ctes(name, x, q, y, r_p, inside) -%}
{{ base.relevant(name, 'x', x) }},
-- the ok final replies that enter the span (a q) or leave it (a y)
{{ name }}_oks as (
    select trace_id, rqst_id, final_t as t, final_seq as seq, {{ base.among(q) }} as enters
    from requests where {{ base.among((q | list) + (y | list)) }} and reply = 'ok'
),
-- per x(i): inside or not, by the latest ok before it, and when that ok came
{{ name }}_state as (
    select x.trace_id, x.rqst_id, any_value(x.t) as t, any_value(x.seq) as seq,
           coalesce(arg_max(o.enters, o.t) filter (where {{ base.before('o.', 'x.') }}), false) as inside,
           max(o.t) filter (where {{ base.before('o.', 'x.') }}) as last_t
    from {{ name }}_x x
    left join {{ name }}_oks o on o.trace_id = x.trace_id and o.rqst_id <> x.rqst_id
    group by x.trace_id, x.rqst_id
),
-- one pair per x(i): it conflicts when x(i) is {{ 'outside' if inside else 'inside' }}. The order
-- of the latest ok before x(i) is sure (the bench sent x(i) after it, rule 7); the first later
-- ok that would change the state could have come first: that distance is movable. shift: the
-- nearer of the two (none: never)
{{ name }}_pairs as (
    select s.trace_id, s.rqst_id, 'state' as item,
           {{ 'not ' if inside }}s.inside as conflicts,
           least(coalesce(s.t - s.last_t, 'infinity'), coalesce(min(o.t - s.t), 'infinity')) as shift,
           coalesce(min(o.t - s.t), 'infinity') as movable,
           false as conflict_rejected
    from {{ name }}_state s
    left join {{ name }}_oks o on o.trace_id = s.trace_id and o.rqst_id <> s.rqst_id
        and o.enters <> s.inside and {{ base.before('s.', 'o.') }}
    group by s.trace_id, s.rqst_id, s.t, s.last_t, s.inside
),
{{ judge.condition(name, movable='p.movable') }},
{{ judge.judged(name, r_p, ['T', 'Z']) }}
{%- endmacro %}
