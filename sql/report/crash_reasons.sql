{#- Why runs crashed: the first line of each crashed trace's error (the line a SUT's stderr
    follows), with how many runs of a campaign and variant gave it, the most frequent first. -#}
with crashed as (
    select campaign_id, sut, coalesce(nullif(split_part(error, chr(10), 1), ''), '(no reason recorded)') as reason
    from traces
    where outcome = 'crashed'
)
select campaign_id, sut, reason, count(*) as runs
from crashed
group by campaign_id, sut, reason
order by campaign_id, runs desc, sut, reason
