{#- Epsilon: how close two events must be for the observed order to be unsure. A real-time run
    measures it: two events closer than the slowest ping round trip of the run may be observed in
    either order (each line can be late by a one-way trip; the round trip bounds both), in mission
    seconds (wall seconds x time_scale), rounded up to 0.1 ms. Any other trace (simulated in
    virtual time, imported) gets the analysis's epsilon (`--epsilon`), or 0 when its SUT replied
    `taken` to every request. Read by the oracles
    (_judge.sql) and by views interface_latency and trace_epsilon.
    The transport's epsilon: a deadline (RSP, CAN, OUTLIVE) compares a reply's instant with an
    instant of the bench's own clock, not two events, so what may blur it is the transport alone:
    the slowest round trip less what the SUT held its pong for (a ROS 2 adapter holds it until the
    node's executor has answered a probe, which the order of events must allow for and a deadline
    must not: a blocked executor is what it measures). -#}

{% macro measured(rtt_s, time_scale) -%}
greatest(ceil({{ rtt_s }} * {{ time_scale }} * 1e4) / 1e4, 1e-4)
{%- endmacro %}

{% macro per_trace(runs=true, taken=true) -%}
-- epsilon per trace: measured by the pings of a real-time run, else the analysis's (`runs`
-- false: a store from before trace_runs, read as it is); 0 for a run without pings whose SUT
-- told the order it took every request in (a `taken` reply each, on the one channel of its
-- replies: every instant an oracle reads then comes in the layer's own order; `taken` false: a
-- store from before taken_events). A real-time run keeps its measured epsilon even then, and an
-- imported trace (it has a label) the analysis's: a live adapter or a recording may learn `taken`
-- and the other replies over different channels (ROS 2's introspection and result topics), whose
-- order neither stdio nor a bag keeps. `source` says which.
epsilons as (
    select trace_id, arg_min(epsilon, epsilon) as epsilon, arg_min(source, epsilon) as source,
           arg_min(transport_epsilon, epsilon) as transport_epsilon from (
{% if runs %}
        -- to_json: a store from before transport_max_s has no such column, and reads it as null
        select trace_id, {{ measured('rtt_max_s', 'time_scale') }} as epsilon, 'pings' as source,
               {{ measured("coalesce((to_json(r)->>'transport_max_s')::double, rtt_max_s)", 'time_scale') }}
                   as transport_epsilon
        from trace_runs r where rtt_max_s is not null
{% else %}
        select null::integer as trace_id, null::double as epsilon, null::varchar as source,
               null::double as transport_epsilon where false
{% endif %}
{% if taken %}
        union all
        select r.trace_id, 0.0, 'taken', 0.0
        from events r left join taken_events k using (trace_id, rqst_id)
        where r.kind = 'request' and r.trace_id in (select trace_id from traces where label is null)
{% if runs %}
            and r.trace_id not in (select trace_id from trace_runs where rtt_max_s is not null)
{% endif %}
        group by r.trace_id having bool_and(k.trace_id is not null)
{% endif %}
    ) group by trace_id
)
{%- endmacro %}
