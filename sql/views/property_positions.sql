-- Each judged property's family and position in the properties file: the order of properties in
-- every table and in the report.
create or replace view property_positions as
select property_id, family, position
from properties
