-- The lifecycle state of a managed ROS 2 node at each request sent to it (docs/ros2.md, "The
-- lifecycle state in the timelines"), derived from the trace alone: its transitions requested
-- and their replies. A module is a managed node when the store holds requests of both its
-- `configure` and `activate` (the services `init --from-ros2` writes for a lifecycle node); a
-- trace starts unconfigured (each run starts the node afresh); a transition's ok (design article
-- "Managed nodes") enters configure -> inactive, activate -> active, deactivate -> inactive,
-- cleanup -> unconfigured, shutdown -> finalized; a refused one changes nothing. The state at a
-- request is the one the last ok before it (in event order) entered; `pending` lists the
-- transitions requested before it whose final reply came after it (the node may be between).
create or replace view lifecycle_states as
with managed as (
    select module
    from events
    where kind = 'request' and service in ('configure', 'activate')
    group by module
    having count(distinct service) = 2
),
transitions as (
    select r.trace_id, r.module, r.service, r.seq, r.final_seq, r.reply
    from requests r join managed using (module)
    where r.service in ('configure', 'activate', 'deactivate', 'cleanup', 'shutdown')
),
entered as (
    select trace_id, module, final_seq,
           case service when 'configure' then 'inactive' when 'activate' then 'active'
                        when 'deactivate' then 'inactive' when 'cleanup' then 'unconfigured'
                        else 'finalized' end as state
    from transitions
    where reply = 'ok'
),
sent as (
    select r.trace_id, r.rqst_id, r.module, r.seq
    from requests r join managed using (module)
),
stated as (
    select s.trace_id, s.rqst_id, s.module, s.seq, coalesce(e.state, 'unconfigured') as state
    from sent s asof left join entered e
        on e.trace_id = s.trace_id and e.module = s.module and s.seq > e.final_seq
),
pending as (
    select s.trace_id, s.rqst_id, string_agg(t.service, ', ' order by t.seq) as pending
    from sent s join transitions t
        on t.trace_id = s.trace_id and t.module = s.module and t.seq < s.seq
       and (t.final_seq is null or t.final_seq > s.seq)
    group by s.trace_id, s.rqst_id
)
select s.trace_id, s.rqst_id, s.module, s.state, p.pending
from stated s left join pending p using (trace_id, rqst_id)
