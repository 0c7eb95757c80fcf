{#- The verdicts table (DESIGN §6), materialised from every property's oracle query.
    `target` is verdicts (observed events) or verdicts_internal (the ground truth). -#}
create or replace table {{ target }} as
with oracle_rows as materialized (
{% for oracle in oracles %}
    select {{ loop.index }} as position, * from (
{{ oracle | indent(8, true) }}
    ){{ ' union all' if not loop.last }}
{% endfor %}
),
-- shared codes: a rejection or interruption that a property did not call for (FP) but that
-- another property with the same code called for on the same request (TP) was enforced for
-- that other property: it is 'op', not FP
enforced as (
    select trace_id, module, service, rqst_id, property_id from oracle_rows where verdict = 'TP'
),
explained as (
    select distinct f.trace_id, f.module, f.service, f.rqst_id, f.property_id
    from oracle_rows f join enforced e using (trace_id, module, service, rqst_id)
    where f.verdict = 'FP' and e.property_id <> f.property_id
)
select o.trace_id, o.property_id, o.family, o.rqst_id, o.module, o.service, o.c_holds,
       case when x.property_id is null then o.verdict else 'op' end as verdict,
       o.margin_s, o.suspicious
from oracle_rows o
left join explained x using (trace_id, module, service, rqst_id, property_id)
-- properties in the order of the properties file, each by trace and request
order by o.position, o.trace_id, o.rqst_id
