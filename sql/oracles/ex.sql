{#- EX[x, y] = ES[x, y] and EE[x, y], exclusion giving priority to y: a request is judged
    by ES when ES calls for its rejection (C_ES false) or it was rejected with r_P,
    otherwise by EE. -#}
{% import 'oracles/es.sql' as es with context %}
{% import 'oracles/ee.sql' as ee with context %}
{% import 'oracles/_judge.sql' as judge with context %}
{% set interrupts = [['x', 'y']] %}{# a y may end an x activity with z_p (its EE side) #}

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
-- the side that judges a request may change with the order of the near events: a request EE
-- judges is judged by ES in an order where ES's C is false (ES's verdicts for C false), and one ES
-- judges for its C alone (not for an r_P reply) by EE in an order where ES's C holds (EE's verdicts)
{{ name }}_es_false as (
    select trace_id, rqst_id, may_hold, reply,
           [case when may_be_na then {{ judge.verdict('false', 'true', r_p, ['T', 'Z']) }} end,
            case when may_fail then {{ judge.verdict('false', 'false', r_p, ['T', 'Z']) }} end] as verdicts
    from {{ name }}_es_verdict
),
{{ name }}_other_side as (
    select f.trace_id, f.rqst_id,
           case when b.rqst_id is null then f.verdicts
                when f.may_hold and f.reply is distinct from {{ r_p | lit }} then list_append(ee.alternatives, ee.verdict)
                else []::varchar[] end as verdicts
    from {{ name }}_es_false f
    join {{ name }}_ee_judged ee using (trace_id, rqst_id)
    left join {{ name }}_by_es b using (trace_id, rqst_id)
),
{{ name }}_sided as (
    select * exclude (property_id) from {{ name }}_es_judged semi join {{ name }}_by_es using (trace_id, rqst_id)
    union all
    select * exclude (property_id) from {{ name }}_ee_judged anti join {{ name }}_by_es using (trace_id, rqst_id)
),
{{ name }}_judged as (
    select j.* replace (list_sort(list_distinct(list_filter(j.alternatives || o.verdicts,
                            lambda other: other is not null and other <> j.verdict))) as alternatives)
    from {{ name }}_sided j join {{ name }}_other_side o using (trace_id, rqst_id)
)
{%- endmacro %}
