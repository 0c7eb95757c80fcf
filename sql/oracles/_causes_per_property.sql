{#- The causes of a one-pass oracle's requests (_parameters.sql: each row of one property), for
    ee.sql; imported `with context` (shared_causes, and what _causes.sql's search reads): from
    the analysis's search, an interruption's and an end from a module of the property's x and y;
    without that search (explain, the in-memory judge: one property), searched as `ctes` does
    with `modules`, the modules of its x and y. -#}
{% import 'oracles/_causes.sql' as causes with context %}

{% macro keyed(name, ended, modules=none) -%}
{% if shared_causes %}
{{ name }}_own_modules as (
    select distinct property_id, module from {{ name }}_services where role in ('x', 'y')
),
{{ name }}_candidates as (
    select e.property_id, c.trace_id, c.rqst_id, c.cause_id, c.module, c.service
    from ({% for e in ended %}select property_id, trace_id, rqst_id from {{ e }}{{ ' union ' if not loop.last }}{% endfor %}) e
    join {{ shared_causes }} c using (trace_id, rqst_id)
    left join {{ name }}_own_modules m on m.property_id = e.property_id and m.module = c.module
    where c.interrupted or m.module is not null
),
{% else %}
{{ name }}_ended as (
    {% for e in ended %}select * exclude (property_id, r_p, z_p) from {{ e }}{{ ' union ' if not loop.last }}{% endfor %}

),
{{ causes.search(name ~ '_one', name ~ '_ended', modules) }},
{{ name }}_candidates as (
    select p.property_id, c.* from {{ name }}_one_candidates c cross join {{ name }}_properties p
),
{% endif %}
{{ causes.sole(name) }}
{%- endmacro %}

