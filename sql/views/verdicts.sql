{#- The verdicts table (DESIGN §6), filled by every property's oracle query in the order of
    the properties file. `target` is verdicts (observed events) or verdicts_internal (the
    ground truth). Several statements, run in the analyzer's transaction. -#}
create or replace table {{ target }} (
    trace_id     integer not null,
    property_id  varchar not null,
    family       varchar not null,
    rqst_id      integer not null,
    module       varchar not null,
    service      varchar not null,
    c_holds      boolean,            -- the P-condition; NULL where it is undefined
    verdict      varchar not null check (verdict in ({{ verdict_names | map('lit') | join(', ') }})),
    margin_s     double,             -- NULL when no event near enough could change C
    suspicious   boolean not null
);

{% for oracle in oracles %}
insert into {{ target }}
{{ oracle }};

{% endfor %}
-- Shared codes: a rejection or interruption that a property did not call for (FP) but that
-- another property with the same code called for on the same request (TP) was enforced for
-- that other property: it is 'op', not FP.
update {{ target }} as v set verdict = 'op'
from (
    select distinct f.trace_id, f.rqst_id, f.property_id
    from {{ target }} f join {{ target }} e using (trace_id, rqst_id)
    where f.verdict = 'FP' and e.verdict = 'TP' and e.property_id <> f.property_id
) as explained
where v.trace_id = explained.trace_id and v.rqst_id = explained.rqst_id
  and v.property_id = explained.property_id;
