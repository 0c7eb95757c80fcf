{#- MX_I[x, y], mutual exclusion by interruption = EE[x, y] and EE[y, x]: the latest
    request interrupts the running activity. Both the x and the y requests are judged,
    under one property id. -#}
{% set judges = ['x', 'y'] %}{# the roles whose requests get verdicts (default: x) #}
{% set interrupts = [['x', 'y'], ['y', 'x']] %}{# each ends the other's activity with z_p #}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/ee.sql' as ee with context %}

{% macro ctes(name, x, y, z_p) -%}
{{ base.both_ways(name, ee.ctes, x, y, z_p) }}
{%- endmacro %}
