-- Traces per campaign, variant and outcome, and which of them Tables II-IV leave out, and why.
with placed as (
    select t.campaign_id, t.sut, t.trace_id, t.outcome, s.counted, s.left_out
    from traces t join trace_scope s using (trace_id)
)
select campaign_id, sut, count(*) as traces,
       count(*) filter (where outcome = 'completed') as completed,
       count(*) filter (where outcome = 'hung') as hung,
       count(*) filter (where outcome = 'crashed') as crashed,
       count(*) filter (where not counted) as not_counted,
       string_agg(distinct left_out, '; ') as left_out_because
from placed
group by campaign_id, sut
order by campaign_id, min(trace_id)
