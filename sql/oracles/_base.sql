{#- Building blocks of every oracle (DESIGN §6), imported by the type templates.
    A request has two instants: (t, seq) when it was sent and (final_t, final_seq) when its
    first final reply came. "Before" is the lexicographic order on (t, seq).

    A type template selects its relevant requests `x` and turns them into `pairs`: one row
    per request x(i) (trace_id, rqst_id) and per thing that can make its P-condition false
    (a y(j), or a service q of Q), saying whether it does (`conflicts`), whether that thing
    was itself rejected (`conflict_rejected`) and how far its events would have to move for
    that to change (`shift`, in seconds). `condition` and `judged` then apply the verdict table. -#}

{% macro among(services) -%}
({% for s in services %}{% set module, service = s.split('.', 1) %}(module = {{ module | lit }} and service = {{ service | lit }}){{ ' or ' if not loop.last }}{% endfor %})
{%- endmacro %}

{% macro relevant(name, role, services) -%}
-- the requests that play the role {{ role }} in this property
{{ name }}_{{ role }} as (
    select * from requests where {{ among(services) }}
)
{%- endmacro %}

{% macro before(a, b) -%}
({{ a }}t < {{ b }}t or ({{ a }}t = {{ b }}t and {{ a }}seq < {{ b }}seq))
{%- endmacro %}

{% macro requests(events, services=none) -%}
-- request and final-reply events (intermediate replies decide nothing)
logged as (
    select trace_id, rqst_id, module, service, kind, t, seq, reply
    from {{ events }}
    where kind in ('request', 'final'){% if services %} and {{ among(services) }}{% endif %}

),
-- one row per request (a request id is unique within its trace): when it was sent, and when
-- and how its first final reply came
paired as (
    select trace_id, rqst_id, any_value(module) as module, any_value(service) as service,
           arg_min(t, seq) filter (where kind = 'request') as t,
           min(seq) filter (where kind = 'request') as seq,
           arg_min(t, seq) filter (where kind = 'final') as final_t,
           min(seq) filter (where kind = 'final') as final_seq,
           arg_min(reply, seq) filter (where kind = 'final') as reply
    from logged
    group by trace_id, rqst_id
),
-- the interface gives each reply code its class T, Z or R; a reply without its request is dropped
requests as (
    select p.*, c.class
    from paired p left join reply_codes c using (module, service, reply)
    where p.seq is not null
)
{%- endmacro %}

{% macro condition(name, defined='true') -%}
-- C per request: false iff some pair conflicts. To flip C, every conflict would have to go
-- (the largest conflicting shift) or any one non-conflict would have to start (the smallest).
{{ name }}_agg as (
    select trace_id, rqst_id,
           bool_or(conflicts) as any_conflict,
           coalesce(bool_and(conflict_rejected) filter (where conflicts), false) as conflicts_rejected,
           case when bool_or(conflicts) then max(shift) filter (where conflicts)
                else min(shift) filter (where not conflicts) end as margin_s
    from {{ name }}_pairs
    group by trace_id, rqst_id
),
{{ name }}_cond as (
    select x.trace_id, x.rqst_id, x.module, x.service, x.reply, x.class,
           case when {{ defined }} then not coalesce(a.any_conflict, false) end as c_holds,
           coalesce(a.conflicts_rejected, false) as conflicts_rejected, a.margin_s
    from {{ name }}_x x left join {{ name }}_agg a using (trace_id, rqst_id)
)
{%- endmacro %}

{% macro judged(name, code, accepted) -%}
-- the verdict table: `code` is the property's own rejection or interruption code, `accepted`
-- the reply classes that mean the activity ran; c_holds NULL = C undefined for this request
{{ name }}_judged as (
    select trace_id, rqst_id, module, service, reply, c_holds,
           case when reply is null then 'omega'
                when c_holds is null then 'op'
                when not c_holds and conflicts_rejected then 'na'
                when reply = {{ code | lit }} then (case when c_holds then 'FP' else 'TP' end)
                when class in ({{ accepted | map('lit') | join(', ') }}) then (case when c_holds then 'TN' else 'FN' end)
                else 'op' end as verdict,
           case when c_holds is not null then nullif(margin_s, 'infinity') end as margin_s
    from {{ name }}_cond
)
{%- endmacro %}

{% macro both_ways(name, ctes, x, y, code) -%}
{{ ctes(name ~ '_xy', x, y, code) }},
{{ ctes(name ~ '_yx', y, x, code) }},
-- a mutual property judges the x requests against y and the y requests against x
{{ name }}_judged as (
    select * from {{ name }}_xy_judged
    union all
    select * from {{ name }}_yx_judged
)
{%- endmacro %}
