-- Which traces Tables II-IV count, and why the others are left out (one row per stored trace).
-- Left out: traces stored after the last analysis (no verdicts yet), the runs of shrinks (table
-- shrink_runs: candidate scripts, not tests), and ad-hoc runs (`python -m harness run`, campaign
-- kind "run") in a store that also holds a campaign or imported traces, so that a run never folds
-- into their per-variant rows. A store of ad-hoc runs alone counts its runs.
create or replace view trace_scope as
with placed as (
    select t.trace_id, t.sut, t.campaign_id,
           t.trace_id in (select trace_id from judged_traces) as judged,
           t.trace_id in (select trace_id from shrink_runs) as shrink_run,
           coalesce(c.config->>'kind' = 'run', false) as ad_hoc
    from traces t left join campaigns c using (campaign_id)
),
reasoned as (
    select *, case when shrink_run then 'run of a shrink (table shrink_runs)'
                   when not judged then 'stored after the last analysis: run analyze'
                   when ad_hoc and exists (select 1 from placed where judged and not ad_hoc and not shrink_run)
                       then 'ad-hoc run beside a campaign or import' end as left_out
    from placed
)
select trace_id, sut, campaign_id, left_out is null as counted, left_out
from reasoned
