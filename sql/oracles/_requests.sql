{#- What every oracle of an analysis shares, made once per events table (the analysis's `shared`
    tables; rendered by harness/analysis/oracles.py): `into`, every request of `events` that some
    oracle reads (of `modules`, whole for the oracles that search causes, or of `services`) with
    its first final reply and class (and its arguments, `args`, when some oracle's template
    declares `needs_args`), from which each oracle reads the requests of its scope
    instead of pairing the events again (25 properties x 2 event tables times over);
    `shared_epsilons`, each trace's epsilon (_epsilon.sql: a pass over every request event, once
    per events table rather than once per oracle); and `shared_causes`, the candidate causes of every
    request's end (_causes.sql's search over all of them, with the `enders` of every property), of
    which each oracle keeps its own. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_epsilon.sql' as eps %}
{% import 'oracles/_causes.sql' as causes with context %}
{% set where %}{{ base.scope(modules) if modules else 'false' }} or {{ base.among(services) if services else 'false' }}{% endset %}
create or replace temp table {{ shared_epsilons }} as
with {{ eps.per_trace(runs, taken) }}
select * from epsilons;

create or replace temp table {{ into }} as
with {{ base.requests(events, where, args=args, taken=taken) }}
select * from requests
order by module, service;

create or replace temp table {{ shared_causes }} as
with requests as (from {{ into }}),
epsilons as (from {{ shared_epsilons }}),
{{ causes.search('every', 'requests', modules) }}
select trace_id, rqst_id, cause_id, module, service, interrupted from every_candidates
