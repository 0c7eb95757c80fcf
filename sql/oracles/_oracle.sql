{#- One property's oracle query (docs/reference/verdicts.md): the requests of its scope in `events` (the
    observed `events` or the ground-truth `internal_events`), its type's CTE chain from
    `template`, and its verdict rows with the contract columns; with `explain`, the pairs that
    decided the condition of some requests instead (explain.requests: (trace_id, rqst_id) pairs);
    with `into`, the statement inserting the verdict rows into that table; with `shared`, the
    table of _requests.sql that holds `events`'s requests (with their arguments when some type
    reads them, as VAL does), read instead of aggregating them again, and the table of each
    trace's epsilon (`shared_epsilons`); with `judged` (a list of properties of one type, each a
    dict of its id, family and parameters), every one of them in one query, through the type's
    `one_pass` macro over their parameter table (_parameters.sql). Rendered by
    harness/analysis/oracles.py. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_epsilon.sql' as eps %}
{% import 'oracles/_parameters.sql' as table %}
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
{% if judged | default(none) %}
{{ table.tables('p', judged) }},
{{ oracle.one_pass('p') }}
select j.trace_id, f.id as property_id, f.family, j.rqst_id, j.module, j.service,
       j.c_holds, j.verdict, j.margin_s, len(j.alternatives) > 0 as suspicious,
       len(j.alternatives) = 0 as certain, j.alternatives
from p_judged j join p_properties f using (property_id)
{% else %}
{{ oracle.ctes('p', **parameters) }}
{% if explain %}
select * from p_pairs where (trace_id, rqst_id) in ({{ explain.requests | join(', ') }})
{% else %}
select trace_id, {{ id | lit }} as property_id, {{ family | lit }} as family, rqst_id, module, service,
       c_holds, verdict, margin_s, len(alternatives) > 0 as suspicious,
       len(alternatives) = 0 as certain, alternatives
from p_judged
{% endif %}
{% endif %}
