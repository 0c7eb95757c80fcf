{#- One property's oracle query (DESIGN §6): the requests of its services in `events` (the
    observed `events` or the ground-truth `internal_events`), its type's CTE chain from
    `template`, and its verdict rows with the contract columns. Rendered by harness/oracles.py. -#}
{% import 'oracles/_base.sql' as base %}
{% import template as oracle %}
with {{ base.requests(events, services) }},
{{ oracle.ctes('p', **parameters) }}
select trace_id, {{ id | lit }} as property_id, {{ family | lit }} as family, rqst_id, module, service,
       c_holds, verdict, margin_s, coalesce(margin_s < {{ epsilon }}, false) as suspicious
from p_judged
