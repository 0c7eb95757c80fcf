-- Every campaign with how many scripts of each kind it made; shrinks are listed with the shrunk
-- reproducers instead.
with listed as (
    select * from campaigns
    where config->>'kind' is distinct from 'shrink'
)
select c.campaign_id, c.created_at, c.mission, c.seed, c.config,
       count(*) filter (where s.kind = 'golden') as golden,
       count(*) filter (where s.kind = 'mutant') as mutants,
       count(*) filter (where s.kind = 'mutant' and not s.valid) as invalid
from listed c left join scripts s using (campaign_id)
group by all
order by c.campaign_id
