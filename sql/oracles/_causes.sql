{#- What ended an activity (docs/analyzer.md, rule 4), for ee.sql's causality rule and for the
    orders it proves (rule 7). Imported `with context` (enders, control, until_stopped, shared_causes).
    An analysis searches the causes of every request once (`search` over all requests, in the
    table _requests.sql makes, named by `shared_causes`); each oracle then keeps those of its own
    requests. Without that table (explain, the in-memory judge) an oracle searches its own. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro sole(name) -%}
-- an end with a single candidate cause orders it: the ended request was taken before its cause,
-- and the cause before that end, whatever the observed order
{{ name }}_sole as (
    select {{ judge.key(true) }}, any_value(cause_id) as cause_id
    from {{ name }}_candidates group by {{ judge.key(true) }} having count(*) = 1
)
{%- endmacro %}

{% macro search(name, ended, modules) -%}
-- An interruption, or the end of an activity that runs until stopped, has a cause: a request
-- sent while it ran (or within epsilon before its request or after its end) and still being
-- processed then (not ended more than epsilon before it). An interruption comes from a request
-- that some property says may end it with that code (`enders`), or from any request to its own
-- module when a property says that module may (an undocumented behaviour such as GenoM's Init,
-- which interrupts with AIB's code); another end from `modules`. A control request replies at
-- once and a rejected one never ran: neither stops anything.
-- per ended service and code, the modules (and, in another module, the service) a cause comes
-- from: y services of x's own module all say "any request to it", so they are one row
{{ name }}_enders as (
    select distinct x_service, reply, split_part(y_service, '.', 1) as module,
           case when split_part(y_service, '.', 1) <> split_part(x_service, '.', 1) then split_part(y_service, '.', 2) end as service
    from (values {% for x_service, code, y_service in enders %}({{ x_service | lit }}, {{ code | lit }}, {{ y_service | lit }}){{ ', ' if not loop.last }}{% else %}(null, null, null){% endfor %}) as e(x_service, reply, y_service)
),
{{ name }}_callers as (
    select * from requests
    where class is distinct from 'R'{% if control %} and not {{ base.among(control) }}{% endif %}

),
-- per request of `ended` whose end needs a cause, the modules it may come from (service NULL: any)
{{ name }}_sources as (
    select x.trace_id, x.rqst_id, x.t, x.seq, x.final_t, x.final_seq, e.module, e.service, true as interrupted
    from {{ ended }} x
    join {{ name }}_enders e on e.x_service = x.module || '.' || x.service and e.reply = x.reply
    where x.class = 'Z'
{% if until_stopped and modules %}
    union all  -- no row twice: the ends above are interruptions (Z), these ran (T)
    select x.trace_id, x.rqst_id, x.t, x.seq, x.final_t, x.final_seq, m.module, null, false
    from {{ ended }} x
    cross join (values {% for m in modules %}({{ m | lit }}){{ ', ' if not loop.last }}{% endfor %}) as m(module)
    where x.class = 'T' and {{ base.among(until_stopped, 'x.') }}  -- it ran and ended: a rejection needs no cause
{% endif %}
),
-- every candidate cause c of each such end (`interrupted`: x(i) was). `low` and `high` bound
-- the instants a cause can be sent at, loosely (a millisecond beyond epsilon, whatever the
-- rounding): a cheap test that spares the exact one most of the pairs of a trace's module
{{ name }}_windows as (
    select x.*, x.t - coalesce(e.epsilon, {{ epsilon }}) - 1e-3 as low,
           x.final_t + coalesce(e.epsilon, {{ epsilon }}) + 1e-3 as high, e.epsilon
    from {{ name }}_sources x left join epsilons e using (trace_id)
),
{{ name }}_candidates as (
    select distinct x.trace_id, x.rqst_id, c.rqst_id as cause_id, c.module, c.service, x.interrupted
    from {{ name }}_windows x
    join {{ name }}_callers c on c.trace_id = x.trace_id and c.module = x.module and c.rqst_id <> x.rqst_id
         and c.t > x.low and (x.high is null or c.t < x.high)
         and (x.service is null or c.service = x.service)
         and ({{ base.before('x.', 'c.') }} or {{ judge.near('x.t - c.t', 'x.epsilon') }})
         and (coalesce({{ base.before('c.', 'x.final_') }}, true) or {{ judge.near('c.t - x.final_t', 'x.epsilon') }})
         and (c.final_t is null or not {{ base.before('c.final_', 'x.final_') }}
              or {{ judge.near('x.final_t - c.final_t', 'x.epsilon') }})
)
{%- endmacro %}
