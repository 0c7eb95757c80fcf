-- Suspicious verdicts, the FN and FP (which make a trace bad) first.
select v.trace_id, t.sut, v.property_id, v.rqst_id, v.module, v.service, v.c_holds,
       v.verdict, v.margin_s
from verdicts v join traces t using (trace_id)
where v.suspicious
order by case v.verdict when 'FN' then 0 when 'FP' then 1 else 2 end, v.trace_id, v.rqst_id, v.property_id
