{#- bench/report_bench.py: every trace (its row, events, ground truth and world events) copied
    `copies` times, copy k under trace id + k * `top` (`top`: the largest trace id stored). -#}
create temporary table copies as select range as k from range(1, {{ copies | int }} + 1);
{% for table in ("traces", "events", "internal_events", "world_events") %}
insert into {{ table }} by name
select t.trace_id + k * {{ top | int }} as trace_id, t.* exclude (trace_id) from {{ table }} t, copies;
{% endfor %}
drop table copies;
