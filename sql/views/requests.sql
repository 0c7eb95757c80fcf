{#- Every request with its first final reply and that reply's class (docs/reference/store.md and docs/reference/verdicts.md): the same
    derivation the oracles use. -#}
{% import 'oracles/_base.sql' as base %}
create or replace view requests as
with {{ base.requests('events') }}
select trace_id, rqst_id, module, service, t, seq, final_t, final_seq, reply, class
from requests
