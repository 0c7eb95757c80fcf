{#- The verdicts table (docs/reference/verdicts.md), filled by the analyzer with every property's oracle query
    in the order of the properties file, then corrected by shared_codes.sql. `target` is
    verdicts (observed events) or verdicts_internal (the ground truth); `temp`: a temporary table
    (where the analyzer stages each oracle's rows); `source`: a table of staged rows, which it
    gets with the shared codes applied. `named`: column -> every value it may hold, stored as an
    enum (its values in byte order, so that rows sort as text does): writing nine million rows of
    repeated text cost three fifths of publishing them. -#}
{% set named = named | default({}) %}
{% macro text(column) %}{% if column in named %}enum({{ named[column] | sort(case_sensitive=true) | map('lit') | join(', ') }}){% else %}varchar{% endif %}{% endmacro %}
create or replace {{ 'temp ' if temp | default(false) }}table {{ target }} (
    trace_id     integer not null,
    property_id  {{ text('property_id') }} not null,
    family       {{ text('family') }} not null,
    rqst_id      integer not null,
    module       {{ text('module') }} not null,
    service      {{ text('service') }} not null,
    c_holds      boolean,            -- the P-condition; NULL where it is undefined
    verdict      {{ text('verdict') }} not null check (verdict in ({{ verdict_names | map('lit') | join(', ') }})),
    margin_s     double,             -- NULL when no event near enough could change C
    suspicious   boolean not null,   -- = not certain: reordering events closer than epsilon could change it
    certain      boolean not null,   -- the verdict holds in every ordering of the events closer than epsilon
    alternatives varchar[] not null  -- the other verdicts those orderings give, sorted; [] when certain
);
{% if source | default(none) %}
insert into {{ target }}
{% include 'views/shared_codes.sql' %}
{% endif %}
