{#- bench/analyzer_bench.py: `traces` traces of `requests` requests each over `services`
    ((module, service) pairs), in one campaign (1) already stored. Every choice (service, timing,
    reply) is a hash of (seed, trace, request), so the same seed gives the same store; `replies`
    are (cumulative percent, reply) pairs, a request past the last one gets no final reply. -#}
insert into traces (trace_id, campaign_id, sut, seed, outcome)
select trace_id, 1, 'variant-' || (trace_id % 3), {{ seed | int }}, 'completed'
from range(1, {{ traces | int }} + 1) r(trace_id);

create temporary table synthetic_requests as
with drawn as (
    select trace_id, rqst_id, hash({{ seed | int }}, trace_id, rqst_id) as h
    from range(1, {{ traces | int }} + 1) a(trace_id), range(1, {{ requests | int }} + 1) b(rqst_id)
),
services(position, module, service) as (
    select row_number() over () - 1, * from (values
    {% for module, service in services %}
        ({{ module | lit }}, {{ service | lit }}){{ "," if not loop.last }}
    {% endfor %}
    )
)
select d.trace_id, d.rqst_id, s.module, s.service,
       -- a request every 0.5 s with jitter; activities last up to 3 s, so they overlap
       d.rqst_id * 0.5 + (d.h >> 8) % 400 / 1000 as t,
       (d.h >> 20) % 3000 / 1000 as duration,
       case
       {% for percent, reply in replies %}
           when (d.h >> 32) % 100 < {{ percent | int }} then {{ reply | lit }}
       {% endfor %}
       end as reply
from drawn d join services s on s.position = d.h % (select count(*) from services);

insert into events (trace_id, seq, t, kind, rqst_id, module, service, args, reply)
with logged as (
    select trace_id, t, 'request' as kind, rqst_id, module, service, null as reply from synthetic_requests
    union all
    select trace_id, t + duration, 'final', rqst_id, module, service, reply
    from synthetic_requests where reply is not null
)
select trace_id, row_number() over (partition by trace_id order by t, kind desc, rqst_id)::integer,
       t, kind, rqst_id, module, service, null, reply
from logged;

drop table synthetic_requests;
