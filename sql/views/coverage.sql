{#- Per variant and property, also where no request was relevant: how many relevant requests
    had the P-condition false (the cases that test enforcement) or true, how many fell in each
    verdict cell, and the TP and FP rates with n and their 95% Wilson intervals; over the traces
    Tables II-IV count (trace_scope), as property_verdicts. -#}
create or replace view coverage as
with variants as (
    select sut, position as variant_rank from variant_positions
    semi join (select sut from trace_scope where counted) using (sut)
),
conditions as (
    select t.sut, v.property_id,
           count(*) filter (where v.c_holds = false) as c_false,
           count(*) filter (where v.c_holds) as c_true
    from verdicts v join trace_scope t using (trace_id)
    where t.counted
    group by all
),
cells as (
    select s.sut, s.variant_rank, p.family, p.property_id, p.position as property_rank,
           coalesce(c.c_false, 0) as c_false, coalesce(c.c_true, 0) as c_true,
{% for verdict in verdict_names %}
           coalesce(pv.{{ verdict | lower }}, 0) as {{ verdict | lower }},
{% endfor %}
           coalesce(pv.suspicious, 0) as suspicious
    from variants s cross join properties p
    left join conditions c using (sut, property_id)
    left join property_verdicts pv using (sut, property_id)
)
select * exclude (variant_rank, property_rank),
       tp / nullif(tp + fn, 0) as tp_rate, tp + fn as tp_n,
       wilson_low(tp, tp + fn) as tp_rate_low, wilson_high(tp, tp + fn) as tp_rate_high,
       fp / nullif(fp + tn, 0) as fp_rate, fp + tn as fp_n,
       wilson_low(fp, fp + tn) as fp_rate_low, wilson_high(fp, fp + tn) as fp_rate_high
from cells
order by variant_rank, property_rank  -- the campaign's and the properties file's order, whatever the plan
