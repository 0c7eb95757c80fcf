{#- bench/same_verdicts.py: how table `table` of the attached stores `b` (before) and `a` (after)
    differs, duplicates counted (except all): its rows on one side only, each way, and its rows after. -#}
with only_before as (from b.{{ table }} except all from a.{{ table }}),
only_after as (from a.{{ table }} except all from b.{{ table }})
select (select count(*) from only_before) as only_before,
       (select count(*) from only_after) as only_after,
       (select count(*) from a.{{ table }}) as rows_after
