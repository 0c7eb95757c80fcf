-- Every shrunk reproducer: the behaviour, the trace it was shrunk from, steps before and after.
with records as (
    select script_id, body, unnest(from_json(mutations, '["json"]')) as r
    from scripts
    where kind = 'shrunk'
)
select script_id, r->>'sut' as sut, r->>'verdict' as verdict, r->>'property' as property_id,
       (r->>'trace')::integer as trace_id, (r->>'steps_before')::integer as steps_before,
       (r->>'steps_after')::integer as steps_after, (r->>'runs')::integer as runs, body
from records
order by script_id
