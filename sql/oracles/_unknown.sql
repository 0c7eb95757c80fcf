{#- The rows of a property whose oracle failed (docs/reference/verdicts.md): verdict 'unknown' on every request
    it judges (`judged`: "module.Service" names), read from `events` without the oracles'
    building blocks, which may be what failed. No ordering of events changes an oracle's failure,
    so the row is certain, with no alternatives (and not suspicious). -#}
insert into {{ into }} by name
select distinct trace_id, {{ id | lit }} as property_id, {{ family | lit }} as family, rqst_id, module, service,
       null::boolean as c_holds, 'unknown' as verdict, null::double as margin_s, false as suspicious,
       true as certain, []::varchar[] as alternatives
from {{ events }}
where kind = 'request' and module || '.' || service in ({{ judged | map('lit') | join(', ') }})
