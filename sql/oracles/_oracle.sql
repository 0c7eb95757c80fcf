{#- One property's oracle query (docs/reference/verdicts.md): the requests of its scope in `events` (the
    observed `events` or the ground-truth `internal_events`), its type's CTE chain from
    `template`, and its verdict rows with the contract columns; with `explain`, the pairs that
    decided the condition of some requests instead (explain.requests: (trace_id, rqst_id) pairs);
    with `into`, the statement inserting the verdict rows into that table; with `shared`, the
    table of _requests.sql that holds `events`'s requests (with their arguments when some type
    reads them, as VAL does), read instead of aggregating them again, and the table of each
    trace's epsilon (`shared_epsilons`). Rendered by
    harness/analysis/oracles.py. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_epsilon.sql' as eps %}
{% import template as oracle with context %}
{% set where = base.scope(modules, services) %}
{% if into %}
insert into {{ into }} by name
{% endif %}
{% if shared %}
-- the analysis's requests, aggregated once for every oracle (_requests.sql); each reference scans
-- them again (they are sorted by module and service: a scan skips the rest), cheaper than a copy
with requests as not materialized (select * from {{ shared }} where {{ where }}),
{% else %}
with {{ base.requests(events, where, explain.traces if explain else none, oracle.needs_args is defined, taken) }},
{% endif %}
{% if shared %}
epsilons as (from {{ shared_epsilons }}),
{% else %}
{{ eps.per_trace(runs, taken) }},
{% endif %}
{{ oracle.ctes('p', **parameters) }}
{% if explain %}
select * from p_pairs where (trace_id, rqst_id) in ({{ explain.requests | join(', ') }})
{% else %}
select trace_id, {{ id | lit }} as property_id, {{ family | lit }} as family, rqst_id, module, service,
       c_holds, verdict, margin_s, len(alternatives) > 0 as suspicious,
       len(alternatives) = 0 as certain, alternatives
from p_judged
{% endif %}
