-- The inverted verdicts (view inversions) with their trace's variant.
select t.sut, i.* from inversions i join traces t using (trace_id)
order by i.trace_id, i.rqst_id, i.property_id
