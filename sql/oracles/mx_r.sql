{#- MX_R[x, y], mutual exclusion by rejection = ES[x, y] and ES[y, x]: the latest request
    is rejected. Both the x and the y requests are judged, under one property id. -#}
{% set judges = ['x', 'y'] %}{# the roles whose requests get verdicts (default: x) #}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/es.sql' as es with context %}
{% import 'oracles/_parameters.sql' as parameters %}

{% macro ctes(name, x, y, r_p) -%}
{{ parameters.tables(name, [{'id': id, 'family': family, 'x': x, 'y': y, 'r_p': r_p}]) }},
{{ one_pass(name, (x + y) | modules) }}
{%- endmacro %}

{#- Every MX_R property at once: ES's one pass over their parameter table, mutual, then over it
    with the roles x and y swapped (mx_i.sql's way with EE). -#}
{% macro one_pass(name, modules=none) -%}
{% for way in ['xy', 'yx'] %}
{{ parameters.swapped(name, way) }},
{{ es.one_pass(name ~ '_' ~ way, modules, mutual=true) }},
{% endfor %}
{{ base.joined(name) }}
{%- endmacro %}
