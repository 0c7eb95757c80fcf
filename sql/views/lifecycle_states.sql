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
sent as (
    select trace_id, rqst_id, module, service, seq, final_seq, reply,
           service in ('configure', 'activate', 'deactivate', 'cleanup', 'shutdown') as transition
    from requests
    where module in (select module from managed)
),
marks as (
    -- each request sent to a node (a transition's with its final reply's place), and each ok of
    -- a transition with the state it enters: one stream per node, so that a filter on the
    -- traces reaches the requests view (a join after it would compute every trace)
    select trace_id, module, seq, rqst_id, null::varchar as entered,
           case when transition then {'service': service, 'final_seq': final_seq} end as requested
    from sent
    union all
    select trace_id, module, final_seq as seq, null as rqst_id,
           case service when 'configure' then 'inactive' when 'activate' then 'active'
                        when 'deactivate' then 'inactive' when 'cleanup' then 'unconfigured'
                        else 'finalized' end as entered, null as requested
    from sent
    where transition and reply = 'ok'
),
stated as (
    select trace_id, rqst_id, module, seq,
           coalesce(last_value(entered ignore nulls) over (node rows between unbounded preceding and current row),
                    'unconfigured') as state,
           list(requested) over (node rows between unbounded preceding and 1 preceding) as before
    from marks
    window node as (partition by trace_id, module order by seq)
)
select trace_id, rqst_id, module, state,
       nullif(array_to_string(list_transform(list_filter(before, lambda t: t is not null
                                                         and (t.final_seq is null or t.final_seq > seq)),
                                             lambda t: t.service), ', '), '') as pending
from stated
where rqst_id is not null
