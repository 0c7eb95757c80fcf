{#- Traces per campaign, variant and outcome, and which of them Tables II-IV leave out, and why. -#}
{% import 'report/_outcomes.sql' as outcomes %}
with placed as (
    select t.campaign_id, t.sut, t.trace_id, t.outcome, s.counted, s.left_out
    from traces t join trace_scope s using (trace_id)
)
select p.campaign_id, p.sut, count(*) as traces,
       {{ outcomes.counts() }},
       count(*) filter (where not p.counted) as not_counted,
       string_agg(distinct p.left_out, '; ') as left_out_because
from placed p join variant_positions v using (sut)
group by p.campaign_id, p.sut
order by p.campaign_id, any_value(v.position)
