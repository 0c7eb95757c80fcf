{#- Shared codes (docs/reference/verdicts.md): the rows of `source` (verdicts staged by every
    property's oracle) as the verdicts table gets them; included by verdicts.sql, which inserts
    them. Applied on the way in rather than by an update afterwards: an update of the published
    table sends its rows through the write-ahead log, and one of the staged table costs a pass too. -#}
-- A rejection or interruption that a property did not call for (FP) but that another property
-- with the same code called for on the same request (TP) was enforced for that other property:
-- it is 'op', not FP. Such a verdict hinges on the other ones: 'op' keeps FP among its
-- alternatives unless a certain TP explains it, and a verdict that is FP in some order (observed,
-- or among its alternatives) gets 'op' among them when another property may be TP in some order.
with fp_able as (  -- the only rows this can change: FP, observed or in some order
    select * from {{ source }} where verdict = 'FP' or list_contains(alternatives, 'FP')
),
tp_able as (  -- the only rows that can make one 'op' or give it 'op' as an alternative
    select * from {{ source }} where verdict = 'TP' or list_contains(alternatives, 'TP')
),
shared as (
    select f.trace_id, f.rqst_id, f.property_id, any_value(f.alternatives) as own,
           case when any_value(f.verdict) = 'FP' and bool_or(e.verdict = 'TP') then 'op'
                else any_value(f.verdict) end as verdict,
           bool_or(e.verdict = 'TP' or list_contains(e.alternatives, 'TP')) as may_be_op,
           bool_or(e.verdict = 'TP' and e.certain) as explained
    from fp_able f join tp_able e using (trace_id, rqst_id)
    where e.property_id <> f.property_id
    group by f.trace_id, f.rqst_id, f.property_id
),
corrected as (
    select trace_id, rqst_id, property_id, verdict,
           list_sort(list_distinct(list_filter(
               own || case when may_be_op then ['op'] else [] end
                   || case when verdict = 'op' and not explained then ['FP'] else [] end,
               lambda other: other <> verdict))) as alternatives
    from shared
)
select * from {{ source }} where not (verdict = 'FP' or list_contains(alternatives, 'FP'))
union all
select v.* replace (coalesce(c.verdict, v.verdict) as verdict,
                    coalesce(c.alternatives, v.alternatives) as alternatives,
                    coalesce(len(c.alternatives) = 0, v.certain) as certain,
                    coalesce(len(c.alternatives) > 0, v.suspicious) as suspicious)
from fp_able v left join corrected c using (trace_id, rqst_id, property_id)
