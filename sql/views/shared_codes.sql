{#- Shared codes (docs/reference/verdicts.md), run on `target` (verdicts or verdicts_internal) once every
    property has inserted its rows. -#}
-- A rejection or interruption that a property did not call for (FP) but that another property
-- with the same code called for on the same request (TP) was enforced for that other property:
-- it is 'op', not FP. Such a verdict hinges on the other one: when no certain TP explains it but
-- an uncertain TP or FP (an FP that may really be a TP) could, the other of FP and op is one of
-- its alternatives too. Only an FP changes: filtering them first spares joining the whole table.
update {{ target }} as v
set verdict = s.verdict,
    alternatives = s.alternatives,
    certain = len(s.alternatives) = 0,
    suspicious = len(s.alternatives) > 0
from (
    select *, list_sort(list_distinct(list_filter(
                  v_alternatives || case when hinges then ['FP', 'op'] else [] end,
                  lambda other: other <> verdict))) as alternatives
    from (
        select f.trace_id, f.rqst_id, f.property_id, any_value(f.alternatives) as v_alternatives,
               case when bool_or(e.verdict = 'TP') then 'op' else 'FP' end as verdict,
               bool_or(not e.certain) and not bool_or(e.verdict = 'TP' and e.certain) as hinges
        from {{ target }} f join {{ target }} e using (trace_id, rqst_id)
        where f.verdict = 'FP' and e.verdict in ('TP', 'FP') and e.property_id <> f.property_id
        group by f.trace_id, f.rqst_id, f.property_id
    )
) as s
where v.verdict = 'FP' and v.trace_id = s.trace_id and v.rqst_id = s.rqst_id and v.property_id = s.property_id
