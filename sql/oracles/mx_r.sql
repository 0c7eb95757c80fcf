{#- MX_R[x, y], mutual exclusion by rejection = ES[x, y] and ES[y, x]: the latest request
    is rejected. Both the x and the y requests are judged, under one property id. -#}
{% set judges = ['x', 'y'] %}{# the roles whose requests get verdicts (default: x) #}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/es.sql' as es with context %}

{% macro mutual(name, x, y, r_p) -%}
{{ es.chain(name, x, y, r_p, mutual=true) }}
{%- endmacro %}

{% macro ctes(name, x, y, r_p) -%}
{{ base.both_ways(name, mutual, x, y, r_p) }}
{%- endmacro %}
