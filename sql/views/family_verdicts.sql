{#- Per variant and family, plus family 'All': the property counts summed. -#}
create or replace view family_verdicts as
select sut, case when grouping(family) = 1 then 'All' else family end as family,
{% for column in ['verdicts'] + verdict_names | map('lower') | list + ['suspicious'] %}
       sum({{ column }})::bigint as {{ column }},
{% endfor %}
{% for verdict in ['tp', 'fn', 'fp', 'tn'] %}
       sum({{ verdict }}_can)::bigint as {{ verdict }}_can,
       sum({{ verdict }}_must)::bigint as {{ verdict }}_must{{ ',' if not loop.last }}
{% endfor %}
from property_verdicts
group by grouping sets ((sut, family), (sut))
