-- bench/generation_bench.py: per property, in the properties' order, how many relevant requests
-- had their P-condition false on the reference variant (the cases that test enforcement).
select property_id, c_false from coverage join properties using (property_id)
where sut = 'reference' order by properties.position
