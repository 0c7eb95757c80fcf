-- The mutants the validator refused (stored, never run), and why.
select script_id, campaign_id, mutations, invalid_reason
from scripts
where not valid
order by script_id
