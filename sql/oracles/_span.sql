{#- The state spans of IN and OUT (docs/reference/properties.md): an ok final reply of a q enters
    a span, an ok of a y leaves it, and a trace starts outside. x(i) is inside when the latest ok
    among Q and Y before it (x(i)'s own reply aside) is a q's. IN's C holds inside, OUT's outside:
    a lifecycle node serves only while active (IN), a transition is offered only in its states.
    While an ok that changes the state is pending at x(i) (its request came before x(i), its ok
    after), which of the two the layer took first cannot be observed (a node that serves them in
    order takes the pending one first): C is undefined, op. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro ctes(name, x, q, y, r_p, inside) -%}
{{ base.relevant(name, 'x', x) }},
-- the ok final replies that enter the span (a q) or leave it (a y)
{{ name }}_oks as (
    select trace_id, rqst_id, final_t as t, final_seq as seq, t as sent_t, seq as sent_seq,
           {{ base.among(q) }} as enters
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
-- per x(i): the later oks that would change its state
{{ name }}_flips as (
    select s.*, o.t as flip_t, o.sent_t, o.sent_seq
    from {{ name }}_state s
    left join {{ name }}_oks o on o.trace_id = s.trace_id and o.rqst_id <> s.rqst_id
        and o.enters <> s.inside and {{ base.before('s.', 'o.') }}
),
-- the x(i) sent while such an ok was pending (C undefined)
{{ name }}_pending as (
    select distinct trace_id, rqst_id from {{ name }}_flips f
    where f.sent_t is not null and {{ base.before('f.sent_', 'f.') }}
),
-- one pair per x(i): it conflicts when x(i) is {{ 'outside' if inside else 'inside' }}. The order
-- of the latest ok before x(i) is sure (the bench sent x(i) after it, rule 7); the first later
-- ok that would change the state could have come first: that distance is movable. shift: the
-- nearer of the two (none: never)
{{ name }}_pairs as (
    select trace_id, rqst_id, 'state' as item, {{ 'not ' if inside }}inside as conflicts,
           least(coalesce(t - last_t, 'infinity'), coalesce(min(flip_t - t), 'infinity')) as shift,
           coalesce(min(flip_t - t), 'infinity') as movable,
           false as conflict_rejected
    from {{ name }}_flips
    group by trace_id, rqst_id, t, last_t, inside
),
{{ judge.condition(name, defined='not exists (select 1 from ' ~ name ~ '_pending n where n.trace_id = x.trace_id '
                   ~ 'and n.rqst_id = x.rqst_id)', movable='p.movable') }},
{{ judge.judged(name, r_p, ['T', 'Z'], undefined_settles=true) }}
{%- endmacro %}
