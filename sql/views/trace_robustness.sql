-- Paper Table II, one row per variant: how many counted traces are bad (view trace_badness) and
-- why; t_rob is the fraction of good traces among those judged good or bad: an `unknown` trace
-- (not bad, but an oracle failed on it) is neither, counted apart in `unknown`, and a variant
-- whose every trace is unknown has no t_rob (NULL). Each count has its interval over the orders of the
-- events closer than epsilon (_min, _max: each trace is bad or not on its own verdicts, so the
-- extremes are the sums of each trace's), and t_rob its interval [t_rob_min, t_rob_max].
create or replace view trace_robustness as
select sut, count(*) as total,
{% for flag in ['hung', 'crashed', 'with_fn', 'with_fp', 'bad', 'unknown'] %}
       count(*) filter (where {{ flag }}) as {{ flag }},
{% endfor %}
       count(*) filter (where not bad and not unknown) / nullif(count(*) filter (where not unknown), 0) as t_rob,
{% for flag in ['with_fn', 'with_fp', 'bad', 'unknown'] %}
       count(*) filter (where {{ flag }}_min) as {{ flag }}_min,
       count(*) filter (where {{ flag }}_max) as {{ flag }}_max,
{% endfor %}
       count(*) filter (where not bad_max and not unknown_min)
           / nullif(count(*) filter (where not unknown_min), 0) as t_rob_min,
       count(*) filter (where not bad_min and not unknown_max)
           / nullif(count(*) filter (where not unknown_max), 0) as t_rob_max
from trace_badness
group by sut
