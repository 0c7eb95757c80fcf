{#- EE[x, y], excluded execution: for an accepted x(i), C false iff some y(j) is sent after
    x(i) and before its final reply (before the end of the trace if it has none).
    C true: T reply TN, z_P FP; C false: T reply FN, z_P TP; another Z code, or a rejected
    x(i) (C undefined), op; no final reply omega; 'na' when every such y(j) was rejected. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro ctes(name, x, y, z_p) -%}
{{ base.relevant(name, 'x', x) }},
{{ base.relevant(name, 'y', y) }},
-- An interruption, or the end of an activity that runs until stopped, has a cause: a request
-- sent while x(i) ran (or within epsilon before its request or after its end) and still being
-- processed then (not ended more than epsilon before it). An interruption comes from a request
-- that some property says may end x with that code (`enders`), or from any request to x's own
-- module when a property says that module may (an undocumented behaviour such as GenoM's Init,
-- which interrupts with AIB's code); another end from the module of x or of y. A control request
-- replies at once and a rejected one never ran: neither stops anything. When every candidate
-- cause is a y(j), one of them stays before the end whatever the observed order: C is false
-- with a conflict that was not rejected (`caused`).
{{ name }}_enders as (
    select * from (values {% for x_service, code, y_service in enders %}({{ x_service | lit }}, {{ code | lit }}, {{ y_service | lit }}){{ ', ' if not loop.last }}{% else %}(null, null, null){% endfor %}) as e(x_service, reply, y_service)
),
{{ name }}_callers as (
    select * from requests
    where class is distinct from 'R'{% if control %} and not {{ base.among(control) }}{% endif %}

),
-- per x(i) whose end needs a cause, the modules it may come from, and the service (NULL: any)
{{ name }}_sources as (
    select x.trace_id, x.rqst_id, x.t, x.seq, x.final_t, x.final_seq, split_part(e.y_service, '.', 1) as module,
           case when split_part(e.y_service, '.', 1) <> x.module then split_part(e.y_service, '.', 2) end as service
    from {{ name }}_x x
    join {{ name }}_enders e on e.x_service = x.module || '.' || x.service and e.reply = x.reply
    where x.class = 'Z'
{% if until_stopped %}
    union
    select x.trace_id, x.rqst_id, x.t, x.seq, x.final_t, x.final_seq, m.module, null
    from {{ name }}_x x
    cross join (values {% for m in (x + y) | modules %}({{ m | lit }}){{ ', ' if not loop.last }}{% endfor %}) as m(module)
    where x.class is distinct from 'Z' and {{ base.among(until_stopped, 'x.') }}
{% endif %}
),
{{ name }}_caused as (
    select x.trace_id, x.rqst_id, bool_and({{ base.among(y, 'c.') }}) as caused
    from {{ name }}_sources x
    left join epsilons e on e.trace_id = x.trace_id
    join {{ name }}_callers c on c.trace_id = x.trace_id and c.module = x.module and c.rqst_id <> x.rqst_id
         and (x.service is null or c.service = x.service)
         and ({{ base.before('x.', 'c.') }} or {{ judge.near('x.t - c.t') }})
         and (coalesce({{ base.before('c.', 'x.final_') }}, true) or {{ judge.near('c.t - x.final_t') }})
         and (c.final_t is null or not {{ base.before('c.final_', 'x.final_') }}
              or {{ judge.near('x.final_t - c.final_t') }})
    group by x.trace_id, x.rqst_id
),
-- each x(i) with every other y(j) of its trace, placed relative to x(i)'s activity
{{ name }}_met as (
    select x.trace_id, x.rqst_id, x.t, x.final_t, y.rqst_id as y_rqst_id, y.t as y_t, y.class as y_class,
           {{ base.before('x.', 'y.') }} as x_first,
           coalesce({{ base.before('y.', 'x.final_') }}, true) as y_before_end
    from {{ name }}_x x
    left join {{ name }}_y y on y.trace_id = x.trace_id and y.rqst_id <> x.rqst_id
),
-- y(j) conflicts if sent while x(i) runs; its shift is how far it would have to move to the
-- other side of x(i)'s request or final reply
{{ name }}_pairs as (
    select trace_id, rqst_id, y_rqst_id::varchar as item,
           x_first and y_before_end as conflicts,
           case when x_first and y_before_end then least(y_t - t, final_t - y_t)
                when x_first then y_t - final_t
                else t - y_t end as shift,
           c.caused,
           y_class is not distinct from 'R' as conflict_rejected
    from {{ name }}_met left join {{ name }}_caused c using (trace_id, rqst_id)
),
{{ judge.condition(name, defined="class is distinct from 'R'", caused='caused') }},
{{ judge.judged(name, z_p, ['T']) }}
{%- endmacro %}
