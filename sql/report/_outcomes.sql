{#- How many traces ended each way (docs/reference/store.md traces.outcome), over the rows of `outcome`. -#}
{% macro counts(outcome='outcome') -%}
count(*) filter (where {{ outcome }} = 'completed') as completed,
       count(*) filter (where {{ outcome }} = 'hung') as hung,
       count(*) filter (where {{ outcome }} = 'crashed') as crashed
{%- endmacro %}
