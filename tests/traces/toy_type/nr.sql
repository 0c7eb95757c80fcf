{#- NR[x, r_p], a toy type for the tests (tests/analysis/test_toy_property_type.py): x is never to be
    rejected with r_P, whatever came before (C always holds). Verdict table of PC with C true:
    accepted TN, r_P FP, another rejection op, no final reply omega. -#}
{% import 'oracles/_base.sql' as base %}
{% import 'oracles/_judge.sql' as judge with context %}

{% macro ctes(name, x, r_p) -%}
{{ base.relevant(name, 'x', x) }},
-- nothing can make C false: no pairs
{{ name }}_pairs as (
    select trace_id, rqst_id, null as item, false as conflicts, 'infinity'::double as shift,
           false as conflict_rejected
    from {{ name }}_x where false
),
{{ judge.condition(name) }},
{{ judge.judged(name, r_p, ['T', 'Z']) }}
{%- endmacro %}
