{#- IN[x, Q, Y], only inside a span: C true iff the latest ok final reply before x(i) among Q and
    Y is a q's (a span entered, not left since; a trace starts outside). E.g. a lifecycle node's
    goals and calls only while it is active: Q = {activate}, Y = {deactivate, shutdown}.
    Verdicts as PC (paper Table I): C true: accepted TN, r_P FP; C false: accepted FN, r_P TP;
    any other rejection op; no final reply omega. -#}
{% import 'oracles/_span.sql' as span with context %}
{% set scope = 'services' %}{# it reads only its own services' requests (x, q, y): it searches no cause #}

{% macro ctes(name, x, q, r_p, y=[]) -%}
{{ span.ctes(name, x, q, y, r_p, true) }}
{%- endmacro %}
