-- Verdicts the interface observation delay changed: the verdict on the observed events
-- against the one the same oracles give on the layer's internal timeline, for the traces
-- that have one. `suspicious` says whether the observed margin flagged it.
create or replace view inversions as
with timed as (
    select distinct trace_id from internal_events
),
observed as (
    select * from verdicts semi join timed using (trace_id)
),
paired as (
    select trace_id, property_id, coalesce(o.family, i.family) as family, rqst_id, module, service,
           o.verdict as observed, i.verdict as internal,
           o.c_holds as observed_c, i.c_holds as internal_c,
           o.margin_s, coalesce(o.suspicious, false) as suspicious
    from observed o full join verdicts_internal i using (trace_id, property_id, module, service, rqst_id)
)
select * from paired
where observed is distinct from internal
