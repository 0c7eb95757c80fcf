{#- The mission seconds a campaign ($campaign) has spent, in two parts: its own traces (golden and
    tests), and the runs of the shrinks of its traces (table shrink_runs). A focused campaign's
    --budget bounds their sum. -#}
with own as (
    select trace_id, sim_s
    from traces
    where campaign_id = $campaign
),
shrinking as (
    select t.sim_s
    from shrink_runs r
    semi join own o on o.trace_id = r.original
    join traces t on t.trace_id = r.trace_id
)
select coalesce((select sum(sim_s) from own), 0.0) as traces_s,
       coalesce((select sum(sim_s) from shrinking), 0.0) as shrink_s
