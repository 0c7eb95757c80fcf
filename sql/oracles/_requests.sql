{#- Every request of `events` with its first final reply and class, aggregated once per analysis
    into the temporary table `into`: each oracle of the analysis reads the requests of its scope
    from it (_oracle.sql's `shared`) instead of grouping the events again, 25 properties x 2
    event tables times over. Rendered by harness/analysis/oracles.py. -#}
{% import 'oracles/_base.sql' as base %}
create or replace temp table {{ into }} as
with {{ base.requests(events, taken=taken) }}
select * from requests
