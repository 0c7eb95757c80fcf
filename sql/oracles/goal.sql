{#- GOAL[x, r_p, deadline], goal policy: a new goal x(j) sent while another goal x(i) of x executes
    is rejected, or preempts x(i): every executing x(i) ends (any final reply) before x(j) moves
    (its first feedback, or its final reply when it succeeded) and within `deadline` of x(j)'s
    sending. C is false iff some x(i) executes at x(j) (not rejected, sent before it, its final
    reply not before it, as in ES). C true: accepted TN, r_P FP, another rejection op, no reply
    omega. C false: rejected (with r_P, or any R without one) TP, another R op; x(j) interrupted
    before it moved op; x(j) moved first, or an x(i) still executing at the deadline, FN; an x(i)
    without a final reply in a trace that ended before the deadline omega; else TP. Not for a
    server that runs goals in parallel by design. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_deadline.sql' as due with context %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}

{% macro table(running, moved_first, late) -%}
case when not {{ running }} then (case when reply is null then 'omega' when class <> 'R' then 'TN'
                                       when own_code then 'FP' else 'op' end)
     when class = 'R' then (case when own_code or not coded then 'TP' else 'op' end)
     when class = 'Z' and first_feedback_t is null then 'op'
     when {{ moved_first }} or {{ late }} then 'FN'
     when last_end_t = 'infinity' then 'omega'
     else 'TP' end
{%- endmacro %}

{% macro ctes(name, x, r_p=none, deadline=none) -%}
{{ base.relevant(name, 'x', x) }},
{{ due.sent(name, x) }},
{{ due.deadlines(name, x, deadline, first_reply=true) }},
{{ due.ends(name, name ~ '_x') }},
{{ name }}_feedback as (
    select trace_id, rqst_id, min(t) as first_feedback_t
    from {{ events }} where kind = 'intermediate' and {{ base.among(x) }} group by trace_id, rqst_id
),
-- each x(j) with every other goal x(i) that ran (not rejected), placed as in ES; a goal without a
-- reply in a trace that ended first may never have been taken (its order unsure: movable 0)
{{ name }}_met as (
    select j.trace_id, j.rqst_id, i.rqst_id::varchar as item, i.final_t as i_final_t,
           {{ base.before('i.', 'j.') }} and not coalesce({{ base.before('i.final_', 'j.') }}, false) as conflicts,
           case when not {{ base.before('i.', 'j.') }} then i.t - j.t
                when {{ base.before('i.final_', 'j.') }} then j.t - i.final_t
                else least(j.t - i.t, coalesce(i.final_t - j.t, 'infinity')) end as shift,
           case when i.final_t is null and {{ judge.ended_first('j.trace_id') }} then 0
                when {{ base.before('i.final_', 'j.') }} then 'infinity'::double  -- rule 7: it ended first
                else null end as sure
    from {{ name }}_x j
    join {{ name }}_x i on i.trace_id = j.trace_id and i.rqst_id <> j.rqst_id and i.class is distinct from 'R'
),
{{ name }}_placed as (
    select m.trace_id, m.rqst_id, m.item, m.conflicts, m.shift, coalesce(m.sure, m.shift) as movable, m.i_final_t,
           {{ judge.near('coalesce(m.sure, m.shift)') }} as near, false as conflict_rejected
    from {{ name }}_met m left join epsilons e using (trace_id)
),
-- per x(j): whether a goal executes at it, how far that is from changing (the largest shift of
-- the conflicts, the smallest of the others), whether any order is unsure, and when the last
-- executing goal ended (infinity: one never did; with the near ones where none executes observed)
{{ name }}_running as (
    select trace_id, rqst_id, bool_or(conflicts) as running, bool_or(near) as some_near,
           case when bool_or(conflicts) then max(shift) filter (where conflicts)
                else min(shift) filter (where not conflicts) end as c_shift,
           coalesce(bool_and(near) filter (where conflicts), false) as running_near,
           case when bool_or(conflicts) then max(coalesce(i_final_t, 'infinity')) filter (where conflicts)
                else max(coalesce(i_final_t, 'infinity')) filter (where near) end as last_end_t
    from {{ name }}_placed
    group by trace_id, rqst_id
),
{{ name }}_facts as (
    select x.*, coalesce({{ 'reply = ' ~ (r_p | lit) if r_p else 'false' }}, false) as own_code, {{ 'true' if r_p else 'false' }} as coded,
           coalesce(r.running, false) as running, r.last_end_t, f.first_feedback_t, d.deadline, e.epsilon,
           least(f.first_feedback_t, case when x.class = 'T' then x.final_t end) as moved_t,
           s.sent_t, s.sent_t + d.deadline as due_t, least(r.last_end_t, n.end_t) as decided_t, r.c_shift,
           coalesce(r.some_near, false) as some_near, coalesce(r.running_near or not r.running and r.some_near, false) as running_near
    from {{ name }}_x x left join {{ name }}_running r using (trace_id, rqst_id)
    left join {{ name }}_feedback f using (trace_id, rqst_id)
    join {{ name }}_sent s using (trace_id, rqst_id) join {{ name }}_deadlines d using (trace_id)
    join {{ name }}_ends n using (trace_id) left join epsilons e using (trace_id)
),
{{ name }}_verdict as (
    select *, coalesce({{ due.after('last_end_t', 'moved_t') }}, false) as moved_first,
           coalesce({{ due.after('decided_t', 'due_t') }}, false) as late,
           some_near or {{ judge.near('abs(last_end_t - moved_t)', 'epsilon') }}
               or moved_t is null and {{ judge.ended_first() }} as moved_near,  -- a feedback may have been lost
           some_near or {{ judge.near('abs(decided_t - due_t)', 'epsilon') }} as late_near
    from {{ name }}_facts
),
-- the items explain shows: the other goals, and the deadline of the executing ones' end
{{ name }}_pairs as (
    select trace_id, rqst_id, item, conflicts, shift, movable, conflict_rejected, null::varchar as detail
    from {{ name }}_placed
    union all
    {% call due.deadline_item(name ~ "_verdict where running") -%}
           printf('sent at %.6f s: the goals executing then due to end by %.6f s (deadline %g s), before it moves (%s); %s',
                  sent_t, due_t, deadline, coalesce(printf('at %.6f s', moved_t), 'never'),
                  case when last_end_t = 'infinity' then 'one never ended' else printf('the last ended at %.6f s', last_end_t) end)
    {%- endcall %}
),
{{ name }}_judged as (
    select trace_id, rqst_id, module, service, reply, not running as c_holds, verdict,
           case when running and class is distinct from 'R' then least(c_shift, abs(decided_t - due_t))
                else nullif(c_shift, 'infinity') end as margin_s,
           list_sort(list_distinct({{ due.options(table, [['running', 'running_near'], ['moved_first', 'moved_near'],
                                                         ['late', 'late_near']]) }}
               || case when reply is null and {{ judge.ended_first() }}  -- its reply may have been lost
                       then list_filter(['FN', 'FP', 'TN', 'TP', 'op'], lambda v: v <> verdict) else [] end)) as alternatives
    from (select *, {{ table('running', 'moved_first', 'late') }} as verdict from {{ name }}_verdict)
)
{%- endmacro %}
