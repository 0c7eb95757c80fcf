-- bench/generation_bench.py: the bad behaviour shown by most traces per (variant, verdict),
-- with a trace showing it, to time its shrinking.
select sut, verdict, property_id, representative from bad_behaviours
qualify row_number() over (partition by sut, verdict order by traces desc) = 1
order by all
