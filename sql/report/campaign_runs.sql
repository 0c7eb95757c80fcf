{#- The runs of one campaign ($campaign) per variant, for the summary a campaign prints. -#}
{% import 'report/_outcomes.sql' as outcomes %}
select t.sut, count(*) as runs,
       {{ outcomes.counts() }},
       sum(t.sim_s) as sim_s
from traces t join variant_positions v using (sut)
where t.campaign_id = $campaign
group by t.sut
order by any_value(v.position)
