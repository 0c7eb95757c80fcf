{#- The parameter table of a one-pass oracle (docs/analyzer.md): the properties of one type as rows,
    so that its query scans, plans and groups the shared requests once for all of them. `judged`:
    one dict per property, its `id`, `family` and parameters (x, y, q: "module.Service" lists; r_p,
    z_p: codes). A type's template that defines `one_pass(name)` reads these two CTEs, and its
    per-property `ctes` gives them one row each (the same chain, for explain and the fallback). -#}
{#- A parameter a property leaves out is absent from its dict (NULL, no services); one a type's `ctes`
    was not given is there, undefined: rendering it fails, naming it. -#}
{% macro code(p, key) %}{{ p[key] | lit if key in p else 'null' }}::varchar{% endmacro %}

{% macro tables(name, judged) -%}
-- per property, its codes; `property_id` is its number here (an integer key groups faster than
-- its text), `id` its id
{{ name }}_properties as (
    select * from (values {% for p in judged %}({{ loop.index }}, {{ p.id | lit }}, {{ p.family | lit }}, {{ code(p, 'r_p') }}, {{ code(p, 'z_p') }}){{ ', ' if not loop.last }}{% endfor %})
        as properties(property_id, id, family, r_p, z_p)
),
-- per property, the services of each of its roles (x, y, q)
{{ name }}_services as (
    select * from (values {% for p in judged %}{% set outer = loop %}{% for role in ['x', 'y', 'q'] %}{% for s in (p[role] if role in p else []) %}{% set module, service = s.split('.', 1) %}({{ outer.index }}, {{ role | lit }}, {{ module | lit }}, {{ service | lit }}), {% endfor %}{% endfor %}{% endfor %}(null, null, null, null))
        as services(property_id, role, module, service) where property_id is not null
)
{%- endmacro %}

{% macro relevant(name, role) -%}
-- each property's requests of the role {{ role }}, with the property's codes
{{ name }}_{{ role }} as (
    select s.property_id, r.*, p.r_p, p.z_p
    from requests r
    join {{ name }}_services s on s.role = {{ role | lit }} and s.module = r.module and s.service = r.service
    join {{ name }}_properties p using (property_id)
)
{%- endmacro %}

{% macro swapped(name, way) -%}
-- the parameter table `name` as `name`_{{ way }}: the roles x and y swapped for 'yx' (a mutual
-- type judges each way with its one-way type's one pass)
{{ name }}_{{ way }}_properties as (from {{ name }}_properties),
{{ name }}_{{ way }}_services as (
    select property_id, {{ "case role when 'x' then 'y' when 'y' then 'x' else role end" if way == 'yx' else 'role' }} as role,
           module, service
    from {{ name }}_services
)
{%- endmacro %}
