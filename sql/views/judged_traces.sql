-- The traces this analysis judged, kept as a table: a trace stored afterwards (an ad-hoc run,
-- an import, a campaign's later runs) has no verdicts yet, and must not count as a good trace.
create or replace table judged_traces as
select trace_id from traces
