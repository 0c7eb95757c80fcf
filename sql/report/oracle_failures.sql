-- The oracles that failed in the last analysis (analyze and campaign print them): one row per
-- property and error, with the events tables it failed on and its 'unknown' verdicts in verdicts.
-- The observed and internal queries render differently (taken replies are observed only), so the
-- same error may sit on other lines of each: one row per error whatever its line, the observed one's shown.
with last_failures as (
    select *, regexp_replace(error, ', line [0-9]+ of the rendered query', '') as cause
    from oracle_failures
    where analysis_id = (select max(analysis_id) from analyses)
),
failed as (
    select property_id, template, arg_min(error, source) as error,
           string_agg(source, ' and ' order by source) as sources
    from last_failures
    group by property_id, template, cause
),
unknown as (
    select property_id, count(*) as verdicts
    from verdicts where verdict = 'unknown' group by all
)
select f.property_id, f.sources, f.template, f.error, coalesce(u.verdicts, 0) as verdicts
from failed f left join unknown u using (property_id)
left join property_positions p using (property_id)
order by p.position, f.error
