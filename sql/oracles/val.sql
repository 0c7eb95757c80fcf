{#- VAL[x] (value domain): C false iff a request x(i) carries an argument outside its domain
    as the interface declares it (docs/targets.md: missing though required, of the wrong JSON
    type, not a finite number, outside min..max, not a choice, not matching the pattern).
    The state-dependent form (y and `domain`): C is also false when an argument is outside
    `domain` while some y(j) runs at x(i) (placed as in ES). The verdict table of PC: C true:
    accepted TN, r_P FP; C false: accepted FN, r_P TP; another R op; no final reply omega;
    'na' when every y(j) that makes C false was itself rejected. `domains` (service -> argument
    -> spec) comes from the interface (harness/analysis/oracles.py). -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_parameters.sql' as parameters %}
{% set needs_args = true %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}

{% macro legal(value, spec) -%}
{%- set text = 'json_extract_string(' ~ value ~ ", '$')" -%}
{%- if spec.type == 'float' -%}
(json_type({{ value }}) in ('DOUBLE', 'BIGINT', 'UBIGINT'){% if spec.min is defined %} and try_cast({{ text }} as double) >= {{ spec.min }}{% endif %}{% if spec.max is defined %} and try_cast({{ text }} as double) <= {{ spec.max }}{% endif %})
{%- else -%}
(json_type({{ value }}) = 'VARCHAR'{% if spec.choices is defined %} and {{ text }} in ({{ spec.choices | map('lit') | join(', ') }}){% endif %}{% if spec.pattern is defined %} and regexp_full_match({{ text }}, {{ spec.pattern | lit }}){% endif %})
{%- endif -%}
{%- endmacro %}

{% macro ctes(name, x, r_p='bad_params', y=[], domain={}) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'y': y, 'r_p': r_p, 'domain': domain}]) }},
{{ one_pass(name, [{'x': x, 'domain': domain}]) }}
{%- endmacro %}

{#- Every VAL property at once, from the parameter table `name`_properties and _services; `props`
    (default: the analysis's `judged`) gives each its x services and `domain`, in the table's order. -#}
{% macro one_pass(name, props=none) -%}
{% set props = props or judged %}
{% set ns = namespace(services=[]) %}{% for p in props %}{% set ns.services = ns.services + p.x %}{% endfor %}
{{ parameters.relevant(name, 'x') }},
{{ parameters.relevant(name, 'y') }},
-- each request of some property's x with each argument its service declares, checked once
-- whatever the number of properties judging it: whether its value is legal
{{ name }}_checked as (
{%- for s in ns.services | unique | sort %}{% set module, service = s.split('.', 1) %}{% for arg, spec in domains[s].items() %}
{%- set value = 'json_extract(args, ' ~ (arg | lit) ~ ')' %}
    select trace_id, rqst_id, {{ module | lit }} as module, {{ service | lit }} as service, {{ arg | lit }} as argument,
           case when {{ value }} is null then {{ 'false' if spec.required else 'true' }}
                else {{ legal(value, spec) }} end as legal,
           {{ value }} as value
    from requests where module = {{ module | lit }} and service = {{ service | lit }}
    union all
{%- endfor %}{% endfor %}
    select null::integer, null::integer, null, null, null, true, null::json where false
),
-- per property, each x(i)'s arguments, and whether each is legal under the property's `domain`
-- too (what must hold while a y runs)
{{ name }}_args as (
    select x.property_id, x.trace_id, x.rqst_id, a.argument, a.legal,
           {% set whens %}{% for p in props %}{% set n = loop.index %}{% for s in p.x %}{% set module, service = s.split('.', 1) %}{% for arg, spec in domains[s].items() if arg in (p.get('domain') or {}) %}
                when x.property_id = {{ n }} and a.module = {{ module | lit }} and a.service = {{ service | lit }}
                     and a.argument = {{ arg | lit }} then a.value is null or {{ legal('a.value', dict(spec, **p.domain[arg])) }}{% endfor %}{% endfor %}{% endfor %}{% endset %}
           {{ 'case' ~ whens ~ ' else true end' if whens.strip() else 'true' }} as legal_while
    from {{ name }}_x x join {{ name }}_checked a using (trace_id, rqst_id)
),
{{ name }}_while as (
    select property_id, trace_id, rqst_id, bool_and(legal_while) as legal_while
    from {{ name }}_args group by property_id, trace_id, rqst_id
),
-- each x(i) with every y(j) of its property in its trace, placed as in ES: y(j) runs at x(i) if
-- sent before it and not ended before it
{{ name }}_met as (
    select x.property_id, x.trace_id, x.rqst_id, x.t, coalesce(w.legal_while, true) as legal_while,
           y.rqst_id as y_rqst_id, y.t as y_t, y.final_t as y_final_t, y.class as y_class,
           {{ base.before('y.', 'x.') }} as y_first,
           coalesce({{ base.before('y.final_', 'x.') }}, false) as y_ended,
           y.final_t is null and {{ judge.ended_first('x.trace_id') }} as y_untaken
    from {{ name }}_x x
    left join {{ name }}_while w using (property_id, trace_id, rqst_id)
    join {{ name }}_y y on y.property_id = x.property_id and y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id
),
-- an argument outside its domain conflicts whatever the timing (no shift changes it); a running
-- y(j) conflicts when x(i) is outside `domain`, its shift that of ES (none if x(i) is inside)
{{ name }}_pairs as (
    select property_id, trace_id, rqst_id, 'arg ' || argument as item, not legal as conflicts,
           'infinity'::double as shift, 'infinity'::double as movable, false as untaken,
           false as conflict_rejected
    from {{ name }}_args
    union all
    select property_id, trace_id, rqst_id, y_rqst_id::varchar as item,
           y_first and not y_ended and not legal_while as conflicts,
           case when legal_while then 'infinity'::double
                when y_first and not y_ended then least(t - y_t, y_final_t - t)
                when y_ended then t - y_final_t
                else y_t - t end as shift,
           case when legal_while then 'infinity'::double
                when y_first and not y_ended and y_untaken then 0  -- it may never have been taken
                when y_first and not y_ended then least(t - y_t, y_final_t - t)
                when y_ended then t - y_final_t
                else y_t - t end as movable,
           y_untaken as untaken,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met
),
{{ judge.condition(name, movable='p.movable', untaken='untaken', keyed=true) }},
{{ judge.judged(name, "coalesce(r_p, 'bad_params')", ['T', 'Z'], keyed=true) }}
{%- endmacro %}
