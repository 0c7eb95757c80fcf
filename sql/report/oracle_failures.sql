-- The oracles that failed in the last analysis (analyze and campaign print them): one row per
-- property and error, with the events tables it failed on and its 'unknown' verdicts in verdicts.
with failed as (
    select property_id, template, error, string_agg(source, ' and ' order by source) as sources
    from oracle_failures
    where analysis_id = (select max(analysis_id) from analyses)
    group by all
),
unknown as (
    select property_id, count(*) as verdicts
    from verdicts where verdict = 'unknown' group by all
)
select f.property_id, f.sources, f.template, f.error, coalesce(u.verdicts, 0) as verdicts
from failed f left join unknown u using (property_id)
left join property_positions p using (property_id)
order by p.position, f.error
