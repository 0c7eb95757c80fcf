{#- Per variant of the taken benchmark (bench/taken_bench.py): its traces, those that hung or crashed,
    the taken replies its SUT made, the verdicts judged on both timelines, the inversions, and how
    many of each the suspicious flag caught. -#}
with judged as (
    select t.sut, v.suspicious
    from verdicts v join traces t using (trace_id)
    semi join verdicts_internal using (trace_id, property_id, module, service, rqst_id)
),
runs as (
    select sut, count(*) as traces, count(*) filter (where outcome <> 'completed') as hung_or_crashed,
           (select count(*) from taken_events k where k.trace_id in
               (select trace_id from traces u where u.sut = t.sut)) as taken_replies
    from traces t group by sut
),
inverted as (
    select t.sut, count(*) as inversions, count(*) filter (where suspicious) as inverted_flagged
    from inversions join traces t using (trace_id) group by t.sut
)
select r.sut, r.traces, r.hung_or_crashed, r.taken_replies, count(j.sut) as judged_on_both,
       coalesce(any_value(i.inversions), 0) as inversions,
       count(j.sut) filter (where j.suspicious) as flagged,
       coalesce(any_value(i.inverted_flagged), 0) as inverted_flagged
from runs r left join judged j using (sut) left join inverted i using (sut)
group by r.sut, r.traces, r.hung_or_crashed, r.taken_replies
order by r.sut
