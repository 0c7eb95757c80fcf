{#- Building blocks of the ROS 2 types (rsp.sql, can.sql, goal.sql, outlive.sql;
    docs/reference/verdicts.md#deadlines): the deadline, the trace's end, a request's sending,
    and the verdicts that the orders of the near events could give. Imported `with context`
    (`events`: the timeline judged). -#}
{% import 'oracles/_base.sql' as base %}
{% set factor = 10 %}{# a derived deadline: this many times the golden runs' largest latency ... #}
{% set floor_s = 1.0 %}{# ... and never less than this, in seconds #}
{% set golden_file = 'golden.mission' %}{# a target's golden mission (harness/target/mission.py GOLDEN_FILE) #}

{% macro deadlines(name, services, deadline=none, first_reply=false) -%}
{% if deadline %}
-- the property's own deadline, in seconds
{{ name }}_deadlines as (
    select trace_id, {{ deadline }}::double as deadline from traces
)
{%- else %}
-- the largest latency, per SUT, of the requests of {{ services | join(', ') }} in its completed golden
-- traces: from the sending to the first final reply{{ ' or feedback' if first_reply }}; read from the
-- observed events whatever the timeline judged, so that both timelines get one deadline
{{ name }}_golden as (
    select g.sut, max(r.replied - r.sent) as latency
    from (select trace_id, rqst_id, min(t) filter (where kind = 'request') as sent,
                 min(t) filter (where kind {{ "<> 'request'" if first_reply else "= 'final'" }}) as replied
          from events
          where {{ base.among(services) }} and trace_id in (
              select trace_id from traces join scripts using (script_id) join campaigns c on c.campaign_id = traces.campaign_id
              where scripts.kind = 'golden' and traces.outcome = 'completed'
                  -- `untimely run` stores any script it runs as golden: only the target's golden is one
                  and (c.config->>'kind' is distinct from 'run' or c.mission like '%/{{ golden_file }}'))
          group by trace_id, rqst_id) r
    join traces g using (trace_id)
    group by g.sut
),
-- the derived deadline: {{ factor }} times that latency, at least {{ floor_s }} s ({{ floor_s }} s without a golden one)
{{ name }}_deadlines as (
    select t.trace_id, greatest({{ factor }} * coalesce(g.latency, 0), {{ floor_s }}) as deadline
    from traces t left join {{ name }}_golden g using (sut)
)
{%- endif %}
{%- endmacro %}

{% macro ends(name, judged) -%}
-- when each trace of the judged requests ended: its run's end, or its last event
{{ name }}_ends as (
    select t.trace_id, greatest(coalesce(any_value(t.sim_s), 0), coalesce(max(e.t), 0)) as end_t
    from traces t left join {{ events }} e using (trace_id)
    where t.trace_id in (select trace_id from {{ judged }})
    group by t.trace_id
)
{%- endmacro %}

{% macro sent(name, services) -%}
-- when each request of {{ services | join(', ') }} was sent (a `taken` reply would hide a wait
-- before the server took it: a deadline runs from the sending)
{{ name }}_sent as (
    select trace_id, rqst_id, t as sent_t from {{ events }} where kind = 'request' and {{ base.among(services) }}
)
{%- endmacro %}

{% macro after(a, b) -%}
(round({{ a }} - {{ b }}, 6) > 0)
{%- endmacro %}

{% macro options(table, facts) -%}
{#- The verdicts other than `verdict` that flipping any of the near facts gives: `facts` is a list
    of [observed, near] SQL booleans, `table` the type's verdict macro of the facts' values. -#}
list_sort(list_distinct(list_filter([
{%- for combo in range(1, 2 ** (facts | length)) %}
{%- set ns = namespace(values=[], near=[]) %}
{%- for fact in facts %}
{%- if (combo // 2 ** loop.index0) % 2 %}
{%- set ns.values = ns.values + ['(not ' ~ fact[0] ~ ')'] %}{% set ns.near = ns.near + [fact[1]] %}
{%- else %}{% set ns.values = ns.values + [fact[0]] %}{% endif %}
{%- endfor %}
    case when {{ ns.near | join(' and ') }} then {{ table(*ns.values) }} end{{ ',' if not loop.last }}
{%- endfor %}
], lambda other: other is not null and other <> verdict)))
{%- endmacro %}

{% macro deadline_item(source) -%}
{#- The item `deadline` that explain shows beside a type's other items: how far the decisive end
    was from the deadline, and `caller()`'s words for it. -#}
select trace_id, rqst_id, 'deadline', false, abs(decided_t - due_t), abs(decided_t - due_t), false,
       {{ caller() }}
    from {{ source }}
{%- endmacro %}
