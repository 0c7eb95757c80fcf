{#- RSP[x, y, deadline], responsiveness: every x(i) (a call, a cancel, a transition) gets its final
    reply, of any class, within `deadline` of its sending. C is false iff some y(j) (a goal)
    executes at x(i): sent before it, not rejected, its final reply not before it (as in ES). The
    verdict does not depend on C (a node late with no goal running is as unresponsive), C only
    says which case a row is: in time TN; late, or no reply while the trace went on past the
    deadline, FN; no reply and the trace ended before the deadline omega. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}
{% import 'oracles/_deadline.sql' as due with context %}
{% set scope = 'services' %}{# it reads only its own services' requests: it searches no cause #}

{% macro table(late) -%}
case when {{ late }} then 'FN' when reply is null then 'omega' else 'TN' end
{%- endmacro %}

{% macro ctes(name, x, y, deadline=none) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
{{ due.sent(name, x) }},
{{ due.deadlines(name, x, deadline) }},
{{ due.ends(name, name ~ '_x') }},
-- each x(i) with its deadline instant, and the instant that decides: its reply, else the trace's end
{{ name }}_timed as (
    select x.*, s.sent_t, d.deadline, s.sent_t + d.deadline as due_t, coalesce(x.final_t, n.end_t) as decided_t,
           e.transport_epsilon
    from {{ name }}_x x join {{ name }}_sent s using (trace_id, rqst_id)
    join {{ name }}_deadlines d using (trace_id) join {{ name }}_ends n using (trace_id)
    left join epsilons e using (trace_id)
),
-- each x(i) with every goal y(j) that ran (not rejected): y(j) executes at x(i) if sent before it
-- and not ended before it; its shift as in ES
{{ name }}_met as (
    select x.trace_id, x.rqst_id, y.rqst_id::varchar as item,
           {{ base.before('y.', 'x.') }} and not coalesce({{ base.before('y.final_', 'x.') }}, false) as conflicts,
           case when not {{ base.before('y.', 'x.') }} then y.t - x.t
                when {{ base.before('y.final_', 'x.') }} then x.t - y.final_t
                else least(x.t - y.t, coalesce(y.final_t - x.t, 'infinity')) end as shift
    from {{ name }}_x x
    join {{ name }}_y y on y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id and y.class is distinct from 'R'
),
-- the items explain shows: the goals, and the deadline (late: it makes the verdict FN)
{{ name }}_pairs as (
    select trace_id, rqst_id, item, conflicts, shift, shift as movable, false as conflict_rejected,
           null::varchar as detail
    from {{ name }}_met
    union all
    {% call due.deadline_item(name ~ "_timed") -%}
           printf('sent at %.6f s, due by %.6f s (deadline %g s), %s at %.6f s', sent_t, due_t, deadline,
                  case when reply is null then 'no reply; the trace ended' else 'answered' end, decided_t)
               || case when {{ due.after('decided_t', 'due_t') }} then ': late' else ': in time' end
    {%- endcall %}
),
{{ name }}_verdict as (
    select t.*, not coalesce(c.running, false) as c_holds, {{ due.after('decided_t', 'due_t') }} as late,
           {{ judge.near('abs(decided_t - due_t)', 'transport_epsilon') }} as late_near
    from {{ name }}_timed t
    left join (select trace_id, rqst_id, bool_or(conflicts) as running from {{ name }}_met
               group by trace_id, rqst_id) c using (trace_id, rqst_id)
),
{{ name }}_judged as (
    select trace_id, rqst_id, module, service, reply, c_holds, verdict, abs(decided_t - due_t) as margin_s,
           {{ due.options(table, [['late', 'late_near']]) }} as alternatives
    from (select *, {{ table('late') }} as verdict from {{ name }}_verdict)
)
{%- endmacro %}
