-- bench/defects.py: the findings whose reproducer was shrunk to at most ? steps.
select sut, property_id, kind, reproducer, reproducer_steps from findings
where reproducer_steps <= ? order by reproducer
