{#- CAN[x, y, z_p, deadline], cancel honoured: a cancel x(i) of a goal g of y. g is the goal its
    arguments name ({"goal": ID}, the request id of g), else the latest request of its goal
    service (`S` for a cancel `S_cancel`, any y if none is so named) sent before it. C is false iff
    g executes at x(i) (not rejected, sent before it, its final reply not before it, as in ES).
    C false: x(i) refused FN (op if g ends z_p in time all the same); g ending z_p within
    `deadline` of x(i)'s sending TP; g ending otherwise, or not by then, FN; g without a final
    reply in a trace that ended before then omega. C true: refused TN, accepted FP (a cancel
    accepted after the goal's end: rclcpp#1569), no reply omega. No goal to cancel: op. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_deadline.sql' as due with context %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}
{% set interrupts = [['y', 'x']] %}{# a cancel may end a goal with z_p: a cause of that end #}

{% macro table(running, late) -%}
case when goal_id is null then (case when reply is null then 'omega' else 'op' end)
     when not {{ running }} then (case when reply is null then 'omega' when class = 'R' then 'TN' else 'FP' end)
     when class = 'R' then (case when ended_z and not {{ late }} then 'op' else 'FN' end)
     when ended_z and not {{ late }} then 'TP'
     when g_final_t is null and not {{ late }} then 'omega'
     else 'FN' end
{%- endmacro %}

{% macro ctes(name, x, y, z_p, deadline=none) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
{{ due.sent(name, x) }},
{{ due.deadlines(name, x, deadline) }},
{{ due.ends(name, name ~ '_x') }},
-- the requests in the bench's order of sending, with the goal a cancel names
{{ name }}_asked as (
    select trace_id, rqst_id, seq, module || '.' || service as qualified,
           try_cast(try_cast(json_extract(args, '$.goal') as double) as integer) as named
    from events where kind = 'request' and {{ base.among(x + y) }}
),
-- the goal each cancel targets (NULL: none)
{{ name }}_targets as (
    select c.trace_id, c.rqst_id,
           case when any_value(c.named) is not null then max(g.rqst_id) filter (where g.rqst_id = c.named)
                else arg_max(g.rqst_id, g.seq) filter (where g.seq < c.seq) end as goal_id
    from {{ name }}_asked c
    left join {{ name }}_asked g on g.trace_id = c.trace_id and ({% for s in x %}{% set named = y | select('equalto', s[:-7]) | list if s.endswith('_cancel') else [] %}
        (c.qualified = {{ s | lit }} and g.qualified in ({{ (named or y) | map('lit') | join(', ') }})){{ ' or' if not loop.last }}{% endfor %})
    where c.qualified in ({{ x | map('lit') | join(', ') }})
    group by c.trace_id, c.rqst_id
),
-- each cancel with its goal, deadline instant, whether the goal runs at it and how far that is
-- from changing (as in ES: a goal whose reply was observed before the cancel ended first, a goal
-- without a reply in a trace that ended first may never have been taken)
{{ name }}_cancels as (
    select x.*, t.goal_id, g.t as g_t, g.final_t as g_final_t, g.class as g_class,
           coalesce(g.reply = {{ z_p | lit }}, false) as ended_z, s.sent_t, d.deadline, s.sent_t + d.deadline as due_t,
           coalesce(g.final_t, n.end_t) as decided_t, e.epsilon, e.transport_epsilon,
           g.class is distinct from 'R' and {{ base.before('g.', 'x.') }}
               and not coalesce({{ base.before('g.final_', 'x.') }}, false) as running,
           case when g.class = 'R' then 'infinity'::double
                when not {{ base.before('g.', 'x.') }} then g.t - x.t
                when {{ base.before('g.final_', 'x.') }} then 'infinity'::double
                when g.final_t is null and {{ judge.ended_first('x.trace_id') }} then 0
                else least(x.t - g.t, coalesce(g.final_t - x.t, 'infinity')) end as movable,
           case when g.class = 'R' then null
                when {{ base.before('g.final_', 'x.') }} then x.t - g.final_t
                else least(abs(x.t - g.t), coalesce(g.final_t - x.t, 'infinity')) end as shift
    from {{ name }}_x x join {{ name }}_targets t using (trace_id, rqst_id)
    left join {{ name }}_y g on g.trace_id = x.trace_id and g.rqst_id = t.goal_id
    join {{ name }}_sent s on s.trace_id = x.trace_id and s.rqst_id = x.rqst_id
    join {{ name }}_deadlines d on d.trace_id = x.trace_id join {{ name }}_ends n on n.trace_id = x.trace_id
    left join epsilons e on e.trace_id = x.trace_id
),
-- the items explain shows: the goal (running: C false), and the deadline of its end
{{ name }}_pairs as (
    select trace_id, rqst_id, goal_id::varchar as item, running as conflicts, shift, movable,
           g_class is not distinct from 'R' as conflict_rejected, null::varchar as detail
    from {{ name }}_cancels where goal_id is not null
    union all
    {% call due.deadline_item(name ~ "_cancels where goal_id is not null") -%}
           printf('cancel sent at %.6f s: goal %s due to end %s by %.6f s (deadline %g s); %s at %.6f s', sent_t,
                  goal_id::varchar, {{ z_p | lit }}, due_t, deadline,
                  case when g_final_t is null then 'no end; the trace ended' else 'it ended' end, decided_t)
               || case when {{ due.after('decided_t', 'due_t') }} then ': late' else ': in time' end
    {%- endcall %}
),
{{ name }}_facts as (
    select *, {{ due.after('decided_t', 'due_t') }} as late, {{ judge.near('movable', 'epsilon') }} as running_near,
           {{ judge.near('abs(decided_t - due_t)', 'transport_epsilon') }} as late_near
    from {{ name }}_cancels
),
{{ name }}_judged as (
    select trace_id, rqst_id, module, service, reply, case when goal_id is not null then not running end as c_holds,
           verdict, case when goal_id is null then null when running then least(shift, abs(decided_t - due_t))
                         else nullif(shift, 'infinity') end as margin_s,
           case when goal_id is null then []::varchar[]
                else list_sort(list_distinct({{ due.options(table, [['running', 'running_near'], ['late', 'late_near']]) }}
                     || case when reply is null and {{ judge.ended_first() }}  -- its reply may have been lost
                             then list_filter(['FN', 'FP', 'TN', 'TP', 'op'], lambda v: v <> verdict) else [] end)) end
               as alternatives
    from (select *, {{ table('running', 'late') }} as verdict from {{ name }}_facts)
)
{%- endmacro %}
