{#- The order of the families: by their first property in the properties file, then 'All' (every
    family, as in view family_verdicts) last. `temp`: a temporary view, for a store analysed
    before this view existed and opened read-only. -#}
create or replace {{ 'temp ' if temp | default(false) }}view family_positions as
with firsts as (
    select family, min(position) as first from property_positions group by family
)
select family, row_number() over (order by first)::integer as position from firsts
union all
select 'All', count(*)::integer + 1 from firsts
