{#- One property's oracle query (DESIGN §6): the requests of its modules in `events` (the
    observed `events` or the ground-truth `internal_events`), its type's CTE chain from
    `template`, and its verdict rows with the contract columns; with `explain`, the pairs that
    decided the condition of some requests instead (explain.requests: (trace_id, rqst_id) pairs);
    with `into`, the statement inserting the verdict rows into that table. Rendered by
    harness/analysis/oracles.py. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_epsilon.sql' as eps %}
{% import template as oracle with context %}
{% if into %}
insert into {{ into }} by name
{% endif %}
with {{ base.requests(events, modules, explain.traces if explain else none, oracle.needs_args is defined, taken) }},
{{ eps.per_trace(runs, taken) }},
{{ oracle.ctes('p', **parameters) }}
{% if explain %}
select * from p_pairs where (trace_id, rqst_id) in ({{ explain.requests | join(', ') }})
{% else %}
select trace_id, {{ id | lit }} as property_id, {{ family | lit }} as family, rqst_id, module, service,
       c_holds, verdict, margin_s, len(alternatives) > 0 as suspicious,
       len(alternatives) = 0 as certain, alternatives
from p_judged
{% endif %}
