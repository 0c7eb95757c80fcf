{#- Building blocks of every oracle (docs/reference/verdicts.md), imported by the type templates.
    A request has two instants: (t, seq) when it was sent, or when the SUT replied that it took
    it (table taken_events), and (final_t, final_seq) when its first final reply came. "Before"
    is the lexicographic order on (t, seq).

    A type template selects its relevant requests `x` and turns them into `pairs`: one row
    per request x(i) (trace_id, rqst_id) and per thing that can make its P-condition false
    (`item`: a y(j)'s request id, or a service q of Q), saying whether it does (`conflicts`),
    whether that thing was itself rejected (`conflict_rejected`) and how far its events would
    have to move for that to change (`shift`, in seconds). `condition` and `judged` of
    _judge.sql then apply the verdict table. -#}

{% macro among(services, of='') -%}
({% for s in services %}{% set module, service = s.split('.', 1) %}({{ of }}module = {{ module | lit }} and {{ of }}service = {{ service | lit }}){{ ' or ' if not loop.last }}{% endfor %})
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

{#- The requests an oracle reads: of its own `services` when its template declares
    `{% set scope = 'services' %}` (a type that searches no cause: PC, VAL), else of their
    `modules` and of every module that may interrupt them (the cause search, _causes.sql). -#}
{% macro scope(modules=none, services=none) -%}
{% if services %}{{ among(services) }}{% elif modules %}module in ({{ modules | map('lit') | join(', ') }}){% else %}true{% endif %}
{%- endmacro %}

{% macro requests(events, where='true', traces=none, args=false, taken=true) -%}
-- the requests that `where` keeps (the requests an oracle reads, see `scope`), one row each (a
-- request id is unique within its trace); `args`: with their arguments (only a value-domain
-- oracle reads them); `taken`: the store has taken_events (one read as it is may lack them)
{% set kept %}({{ where }}){% if traces %} and trace_id in ({{ traces | join(', ') }}){% endif %}{% endset %}
sent as (
    select trace_id, rqst_id, module, service, t, seq{{ ', args' if args }}
    from {{ events }}
    where kind = 'request' and {{ kept }}
),
-- the first final reply of each (intermediate replies decide nothing); joined to its request
-- rather than grouped with it, which costs a sixth of the shared requests' time
finals as (
    select trace_id, rqst_id, arg_min(t, seq) as final_t, min(seq) as final_seq, arg_min(reply, seq) as reply
    from {{ events }}
    where kind = 'final' and {{ kept }}
    group by trace_id, rqst_id
),
-- when each request was sent, and when and how its first final reply came; a reply without its
-- request is dropped
paired as (
    select s.trace_id, s.rqst_id, s.module, s.service, s.t, s.seq, f.final_t, f.final_seq, f.reply{{ ', s.args' if args }}
    from sent s left join finals f using (trace_id, rqst_id)
),
{% if events == 'events' and taken %}
-- observed, a request the SUT replied `taken` to is placed at that reply: the instant the layer
-- took it, observed on the channel of its other replies, instead of its sending
placed as (
    select p.* replace (coalesce(k.t, p.t) as t, coalesce(k.seq, p.seq) as seq)
    from paired p left join taken_events k using (trace_id, rqst_id)
),
{% else %}
placed as (select * from paired),
{% endif %}
-- the interface gives each reply code its class T, Z or R
requests as (
    select p.*, c.class
    from placed p left join reply_codes c using (module, service, reply)
)
{%- endmacro %}

{% macro joined(name) -%}
-- a mutual property judges the x requests against y and the y requests against x
{{ name }}_pairs as (
    select * from {{ name }}_xy_pairs
    union all by name
    select * from {{ name }}_yx_pairs
),
{{ name }}_judged as (
    select * from {{ name }}_xy_judged
    union all
    select * from {{ name }}_yx_judged
)
{%- endmacro %}
