{#- Epsilon: how close two events must be for the observed order to be unsure. A real-time run
    measures it: two events closer than the slowest ping round trip of the run may be observed in
    either order (each line can be late by a one-way trip; the round trip bounds both), in mission
    seconds (wall seconds x time_scale), rounded up to 0.1 ms. Any other trace (simulated in
    virtual time, imported) gets the analysis's epsilon (`--epsilon`). Read by the oracles
    (_judge.sql) and by views interface_latency and trace_epsilon. -#}

{% macro measured(rtt_s, time_scale) -%}
greatest(ceil({{ rtt_s }} * {{ time_scale }} * 1e4) / 1e4, 1e-4)
{%- endmacro %}

{% macro per_trace(runs=true) -%}
-- epsilon per trace: measured by the pings of a real-time run, else the analysis's (`runs`
-- false: a store from before trace_runs, read as it is)
epsilons as (
{% if runs %}
    select trace_id, {{ measured('rtt_max_s', 'time_scale') }} as epsilon
    from trace_runs where rtt_max_s is not null
{% else %}
    select null::integer as trace_id, null::double as epsilon where false
{% endif %}
)
{%- endmacro %}
