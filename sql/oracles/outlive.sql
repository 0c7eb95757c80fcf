{#- OUTLIVE[x, y, deadline], nothing outlives the state: a goal x(i) still executing `deadline`
    after an ok final reply of a y(j) (a transition that leaves the state allowing it, e.g.
    deactivate, cleanup) is an FN, not omega. C is false iff some y(j)'s ok comes while x(i)
    executes (x(i) sent before it, its final reply not before it); the deadline runs from the
    first such ok. A rejected x(i) never ran: op, C undefined. C true: ended TN, no reply omega.
    C false: ended within the deadline TN (by itself, class T) or TP (interrupted, class Z);
    not ended by then FN; no final reply in a trace that ended before then omega. The default
    deadline is derived from y's latencies: how fast the node changes state. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_deadline.sql' as due with context %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}

{% macro table(running, late) -%}
case when class = 'R' then 'op'
     when not {{ running }} then (case when reply is null then 'omega' else 'TN' end)
     when {{ late }} then 'FN'
     when reply is null then 'omega'
     when class = 'Z' then 'TP'
     else 'TN' end
{%- endmacro %}

{% macro ctes(name, x, y, deadline=none) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
{{ due.deadlines(name, y, deadline) }},
{{ due.ends(name, name ~ '_x') }},
-- each x(i) that ran with every ok of a y(j) that it was sent before: it conflicts when x(i) had
-- not ended at that ok; its shift: to x(i)'s sending or its end (sure when x(i) ended first, as
-- observed: rule 7; a goal without a reply in a trace that ended first may never have been taken)
{{ name }}_placed as (
    select x.trace_id, x.rqst_id, y.rqst_id::varchar as item, y.final_t as left_t,
           not coalesce({{ base.before('x.final_', 'y.final_') }}, false) as conflicts,
           case when {{ base.before('x.final_', 'y.final_') }} then y.final_t - x.final_t
                else least(y.final_t - x.t, coalesce(x.final_t - y.final_t, 'infinity')) end as shift,
           case when x.final_t is null and {{ judge.ended_first('x.trace_id') }} then 0
                when {{ base.before('x.final_', 'y.') }} then 'infinity'::double
                when {{ base.before('x.final_', 'y.final_') }} then y.final_t - x.final_t
                else least(y.final_t - x.t, coalesce(x.final_t - y.final_t, 'infinity')) end as movable,
           false as conflict_rejected
    from {{ name }}_x x
    join {{ name }}_y y on y.trace_id = x.trace_id and y.reply = 'ok' and {{ base.before('x.', 'y.final_') }}
    where x.class is distinct from 'R'
    union all  -- a y(j) without a reply in a trace that ended first: its ok may have been lost (rule 10)
    select x.trace_id, x.rqst_id, y.rqst_id::varchar, null, false, null, 0, false
    from {{ name }}_x x
    join {{ name }}_y y on y.trace_id = x.trace_id and y.final_t is null and {{ judge.ended_first('y.trace_id') }}
    where x.class is distinct from 'R' and (x.final_t is null or {{ base.before('y.', 'x.final_') }})
),
-- per x(i): whether it executed when the node left the state, the first such instant, how far C is
-- from changing, and whether any of those orders is unsure (then the first instant is too)
{{ name }}_left as (
    select p.trace_id, p.rqst_id, bool_or(conflicts) as running,
           min(left_t) filter (where conflicts) as left_t, bool_or({{ judge.near('movable') }}) as some_near,
           coalesce(bool_and({{ judge.near('movable') }}) filter (where conflicts), false) as all_near,
           case when bool_or(conflicts) then max(shift) filter (where conflicts)
                else min(shift) filter (where not conflicts) end as c_shift
    from {{ name }}_placed p left join epsilons e using (trace_id)
    group by p.trace_id, p.rqst_id
),
{{ name }}_facts as (
    select x.*, coalesce(l.running, false) as running, l.c_shift, l.left_t + d.deadline as due_t, d.deadline,
           coalesce(x.final_t, n.end_t) as decided_t, e.transport_epsilon,
           coalesce(case when l.running then l.all_near else l.some_near end, false) as running_near,
           coalesce(l.some_near, false) as some_near
    from {{ name }}_x x left join {{ name }}_left l using (trace_id, rqst_id)
    join {{ name }}_deadlines d using (trace_id) join {{ name }}_ends n using (trace_id)
    left join epsilons e using (trace_id)
),
{{ name }}_verdict as (
    select *, coalesce({{ due.after('decided_t', 'due_t') }}, false) as late,
           some_near or {{ judge.near('abs(decided_t - due_t)', 'transport_epsilon') }} as late_near
    from {{ name }}_facts
),
-- the items explain shows: the transitions, and the deadline of the goal's end
{{ name }}_pairs as (
    select trace_id, rqst_id, item, conflicts, shift, movable, conflict_rejected, null::varchar as detail
    from {{ name }}_placed
    union all
    {% call due.deadline_item(name ~ "_verdict where running") -%}
           printf('the node left the state at %.6f s: due to end by %.6f s (deadline %g s); %s at %.6f s',
                  due_t - deadline, due_t, deadline,
                  case when reply is null then 'no end; the trace ended' else 'it ended' end, decided_t)
               || case when late then ': late' else ': in time' end
    {%- endcall %}
),
{{ name }}_judged as (
    select trace_id, rqst_id, module, service, reply, case when class is distinct from 'R' then not running end as c_holds,
           verdict,
           case when class = 'R' then null when running then least(c_shift, abs(decided_t - due_t))
                else nullif(c_shift, 'infinity') end as margin_s,
           case when class = 'R' then []::varchar[]
                else list_sort(list_distinct({{ due.options(table, [['running', 'running_near'], ['late', 'late_near']]) }}
                     || case when reply is null and {{ judge.ended_first() }}  -- its reply may have been lost
                             then list_filter(['TN', 'TP'], lambda v: v <> verdict) else [] end)) end as alternatives
    from (select *, {{ table('running', 'late') }} as verdict from {{ name }}_verdict)
)
{%- endmacro %}
