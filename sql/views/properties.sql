{#- The properties the verdicts were made from, in file order: coverage lists a property even
    where no request was relevant to it. -#}
create or replace table properties (
    property_id  varchar not null,
    family       varchar not null,
    type         varchar not null
);
{% for p in properties %}
insert into properties (property_id, family, type) values ({{ p.id | lit }}, {{ p.family | lit }}, {{ p.type | lit }});
{% endfor %}
