{#- Per variant and property: how many verdicts of each kind, how many are suspicious (not
    certain), and how many FN and FP are certain, over the traces Tables II-IV count (trace_scope). -#}
create or replace view property_verdicts as
select t.sut, v.family, v.property_id, count(*) as verdicts,
{% for verdict in verdict_names %}
       count(*) filter (where v.verdict = {{ verdict | lit }}) as {{ verdict | lower }},
{% endfor %}
       count(*) filter (where v.suspicious) as suspicious,
       count(*) filter (where v.verdict = 'FN' and not v.suspicious) as fn_certain,
       count(*) filter (where v.verdict = 'FP' and not v.suspicious) as fp_certain
from verdicts v join trace_scope t using (trace_id)
where t.counted
group by t.sut, v.family, v.property_id
