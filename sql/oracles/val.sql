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
{{ base.relevant(name, 'x', x) }},
{% if y %}{{ base.relevant(name, 'y', y) }},{% endif %}
-- each x(i) with each argument its service declares: whether its value is legal, and legal
-- under `domain` too (what must hold while a y runs)
{{ name }}_args as (
{%- for s in x %}{% set module, service = s.split('.', 1) %}{% for arg, spec in domains[s].items() %}
{%- set value = 'json_extract(args, ' ~ (arg | lit) ~ ')' %}
    select trace_id, rqst_id, {{ arg | lit }} as argument,
           case when {{ value }} is null then {{ 'false' if spec.required else 'true' }}
                else {{ legal(value, spec) }} end as legal,
           {% if arg in domain %}{{ value }} is null or {{ legal(value, dict(spec, **domain[arg])) }}{% else %}true{% endif %} as legal_while
    from {{ name }}_x where module = {{ module | lit }} and service = {{ service | lit }}
    union all
{%- endfor %}{% endfor %}
    select trace_id, rqst_id, null, true, true from {{ name }}_x where false
),
{% if y %}
{{ name }}_while as (
    select trace_id, rqst_id, bool_and(legal_while) as legal_while
    from {{ name }}_args group by trace_id, rqst_id
),
-- each x(i) with every y(j) of its trace, placed as in ES: y(j) runs at x(i) if sent before it
-- and not ended before it
{{ name }}_met as (
    select x.trace_id, x.rqst_id, x.t, coalesce(w.legal_while, true) as legal_while,
           y.rqst_id as y_rqst_id, y.t as y_t, y.final_t as y_final_t, y.class as y_class,
           {{ base.before('y.', 'x.') }} as y_first,
           coalesce({{ base.before('y.final_', 'x.') }}, false) as y_ended,
           y.final_t is null and {{ judge.ended_first('x.trace_id') }} as y_untaken
    from {{ name }}_x x
    left join {{ name }}_while w using (trace_id, rqst_id)
    join {{ name }}_y y on y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id
),
{% endif %}
-- an argument outside its domain conflicts whatever the timing (no shift changes it); a running
-- y(j) conflicts when x(i) is outside `domain`, its shift that of ES (none if x(i) is inside)
{{ name }}_pairs as (
    select trace_id, rqst_id, 'arg ' || argument as item, not legal as conflicts,
           'infinity'::double as shift, 'infinity'::double as movable, false as untaken,
           false as conflict_rejected
    from {{ name }}_args
{%- if y %}
    union all
    select trace_id, rqst_id, y_rqst_id::varchar as item,
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
{%- endif %}
),
{{ judge.condition(name, movable='p.movable', untaken='untaken') }},
{{ judge.judged(name, r_p, ['T', 'Z']) }}
{%- endmacro %}
