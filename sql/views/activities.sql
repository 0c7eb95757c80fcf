-- Activity intervals: every request that was not rejected, from its request to its final
-- reply; end_t is NULL when it was still running at the end of its trace.
create or replace view activities as
select trace_id, rqst_id, module, service, t as start_t, final_t as end_t,
       final_t - t as duration_s, reply, class
from requests
where class is distinct from 'R'
