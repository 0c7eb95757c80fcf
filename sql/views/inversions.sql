-- Verdicts the interface observation delay changed: the verdict on the observed events against
-- the one the same oracles give on the layer's internal timeline, for the requests judged on
-- both. A request judged on one side only (an omega request of a hung trace that the deadlocked
-- layer never took) is no inversion: no reordering of observed events could change it.
-- `suspicious` says whether the flag caught it.
create or replace view inversions as
with paired as (
    select trace_id, property_id, o.family, rqst_id, module, service,
           o.verdict as observed, i.verdict as internal,
           o.c_holds as observed_c, i.c_holds as internal_c,
           o.margin_s, o.suspicious
    from verdicts o join verdicts_internal i using (trace_id, property_id, module, service, rqst_id)
)
select * from paired
where observed <> internal
