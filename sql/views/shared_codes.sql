{#- Shared codes (docs/reference/verdicts.md), run on `target` (verdicts or verdicts_internal) once every
    property has inserted its rows. -#}
-- A rejection or interruption that a property did not call for (FP) but that another property
-- with the same code called for on the same request (TP) was enforced for that other property:
-- it is 'op', not FP. Such a verdict hinges on the other ones: 'op' keeps FP among its
-- alternatives unless a certain TP explains it, and a verdict that is FP in some order (observed,
-- or among its alternatives) gets 'op' among them when another property may be TP in some order.
update {{ target }} as v
set verdict = s.verdict,
    alternatives = s.alternatives,
    certain = len(s.alternatives) = 0,
    suspicious = len(s.alternatives) > 0
from (
    select *, list_sort(list_distinct(list_filter(
                  own || case when may_be_op then ['op'] else [] end
                      || case when verdict = 'op' and not explained then ['FP'] else [] end,
                  lambda other: other <> verdict))) as alternatives
    from (
        select f.trace_id, f.rqst_id, f.property_id, any_value(f.alternatives) as own,
               case when any_value(f.verdict) = 'FP' and bool_or(e.verdict = 'TP') then 'op'
                    else any_value(f.verdict) end as verdict,
               bool_or(e.verdict = 'TP' or list_contains(e.alternatives, 'TP')) as may_be_op,
               bool_or(e.verdict = 'TP' and e.certain) as explained
        from {{ target }} f join {{ target }} e using (trace_id, rqst_id)
        where (f.verdict = 'FP' or list_contains(f.alternatives, 'FP')) and e.property_id <> f.property_id
        group by f.trace_id, f.rqst_id, f.property_id
    )
) as s
where v.trace_id = s.trace_id and v.rqst_id = s.rqst_id and v.property_id = s.property_id
