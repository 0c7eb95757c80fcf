-- What went wrong in each trace, one row per (property, kind): an FN or FP verdict on a property,
-- or the trace hung or crashed (property null). The one rule of a finding: the views
-- bad_behaviours and findings, and a focused campaign's stopping rule (on its in-memory judge),
-- all read it. The runs of shrinks (table shrink_runs) show no findings: they re-run a finding.
create or replace {{ 'temp ' if temp | default(false) }}view trace_findings as
with wrong_verdicts as (
    select distinct trace_id, property_id, verdict as kind
    from verdicts
    where verdict in ('FN', 'FP')
),
wrong_outcomes as (
    select trace_id, null as property_id, outcome as kind
    from traces
    where outcome in ('hung', 'crashed')
),
shown as (
    select * from wrong_verdicts
    union all
    select * from wrong_outcomes
)
select s.trace_id, t.sut, s.property_id, s.kind
from shown s join traces t using (trace_id)
anti join shrink_runs r using (trace_id)
