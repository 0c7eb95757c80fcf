{#- What lies behind a trace's row in a list: its FN/FP verdicts' properties (else its TPs'), from
    verdict rows v (the lists add the mutation that made the trace's script). -#}
{% macro behind() -%}
coalesce(string_agg(distinct v.property_id, ' ' order by v.property_id) filter (where v.verdict in ('FN', 'FP')),
                      string_agg(distinct v.property_id, ' ' order by v.property_id) filter (where v.verdict = 'TP')) as properties
{%- endmacro %}
