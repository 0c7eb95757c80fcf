{#- Shared codes (DESIGN §6), run on `target` (verdicts or verdicts_internal) once every
    property has inserted its rows. -#}
-- A rejection or interruption that a property did not call for (FP) but that another property
-- with the same code called for on the same request (TP) was enforced for that other property:
-- it is 'op', not FP. Such a verdict hinges on the other one: it is suspicious too when no sure
-- TP explains it but a suspicious TP or FP (an FP that may really be a TP) could.
update {{ target }} as v
set verdict = case when s.explained then 'op' else v.verdict end,
    suspicious = v.suspicious or s.hinges_on_suspicious
from (
    select f.trace_id, f.rqst_id, f.property_id,
           bool_or(e.verdict = 'TP') as explained,
           bool_or(e.suspicious) and not bool_or(e.verdict = 'TP' and not e.suspicious) as hinges_on_suspicious
    from {{ target }} f join {{ target }} e using (trace_id, rqst_id)
    where f.verdict = 'FP' and e.verdict in ('TP', 'FP') and e.property_id <> f.property_id
    group by f.trace_id, f.rqst_id, f.property_id
) as s
where v.trace_id = s.trace_id and v.rqst_id = s.rqst_id and v.property_id = s.property_id
