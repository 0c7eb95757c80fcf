{#- Per (variant, family or All): the counted traces with a TP, FN or FP in that family, worst
    first. Family 'All' is every family of the variant, as in view family_verdicts. -#}
{% import 'report/_behind.sql' as lists %}
with counted as (
    select v.*, t.sut, t.outcome, t.script_id
    from verdicts v join trace_scope c using (trace_id) join traces t using (trace_id)
    where c.counted
),
per_family as (
    select v.sut, case when grouping(v.family) = 1 then 'All' else v.family end as family, v.trace_id,
           any_value(v.outcome) as outcome,
           count(*) filter (where v.verdict = 'FN') as fn, count(*) filter (where v.verdict = 'TP') as tp,
           count(*) filter (where v.verdict = 'FP') as fp, count(*) filter (where v.verdict = 'TN') as tn,
           {{ lists.behind() }}
    from counted v left join scripts s using (script_id)
    group by grouping sets ((v.sut, v.family, v.trace_id, s.mutations), (v.sut, v.trace_id, s.mutations))
)
select * from per_family
where fn + tp + fp > 0
order by fn desc, fp desc, tp desc, trace_id, sut, family
