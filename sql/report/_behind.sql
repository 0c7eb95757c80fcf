{#- What lies behind a trace's row in a list: its FN/FP verdicts' properties (else its TPs'), and
    the mutation that made its script (reads verdicts v and scripts s). -#}
{% macro behind() -%}
coalesce(string_agg(distinct v.property_id, ' ' order by v.property_id) filter (where v.verdict in ('FN', 'FP')),
                      string_agg(distinct v.property_id, ' ' order by v.property_id) filter (where v.verdict = 'TP')) as properties,
             s.mutations
{%- endmacro %}
