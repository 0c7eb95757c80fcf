-- Every FN and FP verdict, with its trace's variant and outcome.
select v.trace_id, t.sut, t.outcome, v.property_id, v.family, v.rqst_id, v.module, v.service,
       v.c_holds, v.verdict, v.margin_s, v.suspicious
from verdicts v join traces t using (trace_id)
where v.verdict in ('FN', 'FP')
order by v.trace_id, v.rqst_id, v.property_id
