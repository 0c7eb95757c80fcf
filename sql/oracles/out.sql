{#- OUT[x, Q, Y], only outside every span: C true iff no ok final reply of Q and Y came before
    x(i), or the latest one is a y's (see in.sql). E.g. a lifecycle node's configure only while
    unconfigured: Q = {configure, shutdown}, Y = {cleanup}; its shutdown only until it is
    finalized: Q = {shutdown}, no Y. Verdicts as PC. -#}
{% import 'oracles/_span.sql' as span with context %}
{% set scope = 'services' %}{# it reads only its own services' requests (x, q, y): it searches no cause #}

{% macro ctes(name, x, q, r_p, y=[]) -%}
{{ span.ctes(name, x, q, y, r_p, false) }}
{%- endmacro %}
