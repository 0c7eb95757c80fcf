{% import 'oracles/_epsilon.sql' as epsilon %}
-- The interface latency of real-time runs, per campaign and SUT, from the liveness pings'
-- round trips (wall seconds, trace_runs), and the epsilon of its slowest run (sql/oracles/_epsilon.sql;
-- each trace is judged with its own, view trace_epsilon); none without pings.
create or replace view interface_latency as
with runs as (
    select t.campaign_id, t.sut, r.*
    from trace_runs r join traces t using (trace_id)
),
per_sut as (
    select campaign_id, sut, count(*) as runs, sum(pings) as pings, max(time_scale) as time_scale,
           median(rtt_p50_s) as rtt_p50_s,
           quantile_cont(rtt_p95_s, 0.95) as rtt_p95_s,
           max(rtt_max_s) as rtt_max_s
    from runs
    group by campaign_id, sut
)
select *, case when rtt_max_s is not null then {{ epsilon.measured('rtt_max_s', 'time_scale') }} end as suggested_epsilon_s
from per_sut
