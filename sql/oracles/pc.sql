{#- PC[x, Q], precondition: C true iff every q in Q has an ok final reply before x(i).
    Paper Table I: C true: accepted TN, r_P FP; C false: accepted FN, r_P TP;
    any other rejection op; no final reply omega. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_parameters.sql' as parameters %}
{% import 'oracles/_judge.sql' as judge with context %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}

{% macro ctes(name, x, q, r_p) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'q': q, 'r_p': r_p}]) }},
{{ one_pass(name) }}
{%- endmacro %}

{#- Every PC property at once, from the parameter table `name`_properties and _services. -#}
{% macro one_pass(name) -%}
{{ parameters.relevant(name, 'x') }},
-- each q's first ok reply in each trace, in the order of (t, seq): some ok of q precedes x(i) iff
-- the first does, and the distances below are the first's (the earliest ok before x(i), or the
-- first after it), so x(i) is paired with it alone rather than with every ok of its trace; one
-- grouping for every property's Q
{{ name }}_first_oks as (
    select trace_id, module, service, min({'t': final_t, 'seq': final_seq}) as first
    from requests semi join {{ name }}_services q on q.role = 'q' and q.module = requests.module and q.service = requests.service
    where reply = 'ok'
    group by trace_id, module, service
),
-- one pair per x(i) and q in its property's Q: q conflicts while none of its ok replies precedes
-- x(i). Its shift: back to the earliest ok before x(i), or on to the first ok after it (none: never)
{{ name }}_pairs as (
    select x.property_id, x.trace_id, x.rqst_id, n.module || '.' || n.service as item,
           not coalesce({{ base.before('o.first.', 'x.') }}, false) as conflicts,
           case when {{ base.before('o.first.', 'x.') }} then x.t - o.first.t
                else coalesce(o.first.t - x.t, 'infinity') end as shift,
           -- rule 7: an ok observed before x(i) was sent came before it whatever the delays
           case when {{ base.before('o.first.', 'x.') }} then 'infinity'::double
                else coalesce(o.first.t - x.t, 'infinity') end as movable,
           false as conflict_rejected
    from {{ name }}_x x
    join {{ name }}_services n on n.property_id = x.property_id and n.role = 'q'
    left join {{ name }}_first_oks o on o.trace_id = x.trace_id and o.module = n.module and o.service = n.service
),
{{ judge.condition(name, movable='p.movable', keyed=true) }},
{{ judge.judged(name, 'r_p', ['T', 'Z'], keyed=true) }}
{%- endmacro %}
