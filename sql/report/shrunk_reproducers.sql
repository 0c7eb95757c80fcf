-- Every shrunk reproducer: the behaviour, the trace it was shrunk from, steps before and after.
{% import 'report/_shrinks.sql' as shrinks %}
with records as (
    {{ shrinks.shrunk_scripts() }}
)
select script_id, sut, verdict, property_id, trace_id, steps_before, steps_after, runs, body
from records
order by script_id
