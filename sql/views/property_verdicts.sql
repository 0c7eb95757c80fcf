{#- Per variant and property: how many verdicts of each kind, how many are suspicious (not
    certain), over the traces Tables II-IV count (trace_scope); and for TP, FN, FP and TN how many
    verdicts could be one (`_can`: it or one of its alternatives) and must be one (`_must`: certain),
    the counts the intervals of Tables III and IV are computed from. -#}
create or replace view property_verdicts as
select t.sut, v.family, v.property_id, count(*) as verdicts,
{% for verdict in verdict_names %}
       count(*) filter (where v.verdict = {{ verdict | lit }}) as {{ verdict | lower }},
{% endfor %}
{% for verdict in ['TP', 'FN', 'FP', 'TN'] %}
       count(*) filter (where can_be(v.verdict, v.alternatives, [{{ verdict | lit }}])) as {{ verdict | lower }}_can,
       count(*) filter (where must_be(v.verdict, v.alternatives, [{{ verdict | lit }}])) as {{ verdict | lower }}_must,
{% endfor %}
       count(*) filter (where v.suspicious) as suspicious
from verdicts v join trace_scope t using (trace_id)
where t.counted
group by t.sut, v.family, v.property_id
