{#- EX[x, y] = ES[x, y] and EE[x, y], exclusion giving priority to y: a request is judged
    by ES when ES calls for its rejection (C_ES false) or it was rejected with r_P,
    otherwise by EE. -#}
{% import 'oracles/es.sql' as es with context %}
{% import 'oracles/ee.sql' as ee with context %}

{% macro ctes(name, x, y, r_p, z_p) -%}
{{ es.ctes(name ~ '_es', x, y, r_p) }},
{{ ee.ctes(name ~ '_ee', x, y, z_p) }},
{{ name }}_by_es as (
    select trace_id, rqst_id from {{ name }}_es_judged
    where not c_holds or reply = {{ r_p | lit }}
),
-- both sides' pairs, for explaining a verdict
{{ name }}_pairs as (
    select 'ES' as part, * from {{ name }}_es_pairs
    union all by name
    select 'EE' as part, * from {{ name }}_ee_pairs
),
{{ name }}_judged as (
    select * from {{ name }}_es_judged semi join {{ name }}_by_es using (trace_id, rqst_id)
    union all
    select * from {{ name }}_ee_judged anti join {{ name }}_by_es using (trace_id, rqst_id)
)
{%- endmacro %}
