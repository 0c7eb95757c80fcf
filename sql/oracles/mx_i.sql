{#- MX_I[x, y], mutual exclusion by interruption = EE[x, y] and EE[y, x]: the latest
    request interrupts the running activity. Both the x and the y requests are judged,
    under one property id. -#}
{% set judges = ['x', 'y'] %}{# the roles whose requests get verdicts (default: x) #}
{% set interrupts = [['x', 'y'], ['y', 'x']] %}{# each ends the other's activity with z_p #}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/ee.sql' as ee with context %}

{% import 'oracles/_parameters.sql' as parameters %}

{% macro ctes(name, x, y, z_p) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'y': y, 'z_p': z_p}]) }},
{{ one_pass(name, (x + y) | modules) }}
{%- endmacro %}

{#- Every MX_I property at once: EE's one pass over their parameter table, then over it with the
    roles x and y swapped. -#}
{% macro one_pass(name, modules=none) -%}
{% for way in ['xy', 'yx'] %}
{{ parameters.swapped(name, way) }},
{{ ee.one_pass(name ~ '_' ~ way, modules) }},
{% endfor %}
{{ base.joined(name) }}
{%- endmacro %}
