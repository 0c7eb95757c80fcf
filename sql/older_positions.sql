{#- The positions a store written before schema version 3 (or analysed before it) lacks, derived
    as the bench that wrote it ordered its rows: variants by their first trace, modules by their
    first reply code, properties by the properties table (else by their first verdict), families
    by their first property. `missing`: the relations it lacks. With `temp`, temporary views for
    a store opened read-only; otherwise the migration to version 3 keeps them for good (the next
    analysis replaces the properties' and families' views by its own). -#}
{% set view = 'create temp view' if temp else 'create or replace view' %}
{% macro kept(table, columns) %}{{ view ~ ' ' ~ table ~ ' as' if temp else 'insert into ' ~ table ~ ' (' ~ columns ~ ')' }}{% endmacro %}
{% if 'variant_positions' in missing %}
{{ kept('variant_positions', 'sut, position') }}
select sut, row_number() over (order by min(trace_id))::integer as position
from traces group by sut;
{% endif %}
{% if 'module_positions' in missing %}
{{ kept('module_positions', 'module, position') }}
select module, row_number() over (order by min(rowid))::integer as position
from reply_codes group by module;
{% endif %}
{% if 'property_positions' in missing %}
{{ view }} property_positions as
{% if 'properties' not in missing %}
select property_id, family, (rowid + 1)::integer as position from properties;
{% elif 'verdicts' not in missing %}
select property_id, any_value(family) as family, min(rowid)::integer as position
from verdicts group by property_id;
{% else %}
select null::varchar as property_id, null::varchar as family, null::integer as position limit 0;
{% endif %}
{% endif %}
{% if 'family_positions' in missing %}
{% include 'views/family_positions.sql' %};
{% endif %}
