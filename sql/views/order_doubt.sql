-- Per variant, how much of its intervals (Tables II-IV) the SUT's own timestamps would remove:
-- where it tells the order it took every request in (a `taken` reply each, trace_epsilon's source
-- 'taken'), no two events are in doubt and a completed trace's verdicts are all certain, so its
-- intervals shrink to points. `told_traces` of `traces` already do; `settled` uncertain verdicts
-- of completed traces the stamps would settle, `unsettled` those of traces that ended first (hung,
-- crashed: a request may never have been taken, a reply lost, whatever the stamps); then the width
-- of each interval (percentage points of a rate, traces of a count), the most the stamps remove.
create or replace view order_doubt as
with counted as (
    select s.trace_id, s.sut, t.outcome = 'completed' as completed, e.source = 'taken' as told
    from trace_scope s join traces t using (trace_id) join trace_epsilon e using (trace_id)
    where s.counted
),
doubts as (
    select c.sut, count(*) filter (where not v.certain and c.completed) as settled,
           count(*) filter (where not v.certain and not c.completed) as unsettled
    from verdicts v join counted c using (trace_id)
    group by c.sut
),
traced as (
    select sut, count(*) as traces, count(*) filter (where told) as told_traces from counted group by sut
)
select t.sut, t.traces, t.told_traces, coalesce(d.settled, 0) as settled, coalesce(d.unsettled, 0) as unsettled,
       r.bad_max - r.bad_min as bad_width, r.t_rob_max - r.t_rob_min as t_rob_width,
       tp.tp_rate_max - tp.tp_rate_min as tp_rate_width, fp.fp_rate_max - fp.fp_rate_min as fp_rate_width
from traced t
left join doubts d using (sut)
left join trace_robustness r using (sut)
left join tp_rates tp on tp.sut = t.sut and tp.family = 'All'
left join fp_rates fp on fp.sut = t.sut and fp.family = 'All'
