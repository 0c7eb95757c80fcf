{#- The properties the verdicts were made from, with their position in the properties file:
    coverage lists a property even where no request was relevant to it, and every table lists
    properties and families in file order (views property_positions, family_positions). -#}
create or replace table properties (
    property_id  varchar not null,
    family       varchar not null,
    type         varchar not null,
    position     integer not null
);
{% for p in properties %}
insert into properties (property_id, family, type, position) values ({{ p.id | lit }}, {{ p.family | lit }}, {{ p.type | lit }}, {{ loop.index }});
{% endfor %}
