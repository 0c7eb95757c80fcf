{#- Per (variant, family or All): the counted traces with a TP, FN or FP in that family, worst
    first. Family 'All' is every family of the variant, as in view family_verdicts. The verdicts
    are first counted per trace, family, verdict and property (a TN without its property: it is
    only counted), and the variant, outcome and mutation joined after: the ordered string_agg of
    lists.behind() cannot spill to disk, and so holds a few rows per trace (40 MB of DuckDB memory
    at 10,000 traces instead of 80). -#}
{% import 'report/_behind.sql' as lists %}
with counted as (
    select trace_id, family, verdict, if(verdict = 'TN', null, property_id) as property_id
    from verdicts semi join (select trace_id from trace_scope where counted) using (trace_id)
    where verdict in ('TP', 'FN', 'FP', 'TN')
),
per_property as (
    select trace_id, family, verdict, property_id, count(*) as n
    from counted
    group by all
),
per_family as (
    select v.trace_id, case when grouping(v.family) = 1 then 'All' else v.family end as family,
           coalesce(sum(v.n) filter (where v.verdict = 'FN'), 0)::bigint as fn,
           coalesce(sum(v.n) filter (where v.verdict = 'TP'), 0)::bigint as tp,
           coalesce(sum(v.n) filter (where v.verdict = 'FP'), 0)::bigint as fp,
           coalesce(sum(v.n) filter (where v.verdict = 'TN'), 0)::bigint as tn,
           {{ lists.behind() }}
    from per_property v
    group by grouping sets ((v.trace_id, v.family), (v.trace_id))
),
listed as (
    select t.sut, f.family, f.trace_id, t.outcome, f.fn, f.tp, f.fp, f.tn, f.properties, s.mutations
    from per_family f join traces t using (trace_id) left join scripts s using (script_id)
    where f.fn + f.tp + f.fp > 0
)
select * from listed
order by fn desc, fp desc, tp desc, trace_id, sut, family
