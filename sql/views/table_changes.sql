-- The cells of Tables II-IV that the last analysis changed (table_values_previous holds the
-- values of the analysis before it). A rate that became NULL or stopped being NULL counts.
create or replace view table_changes as
with compared as (
    select sut, family, paper_table, measure, p.value as previous, c.value as current
    from table_values_previous p full join table_values c using (sut, family, paper_table, measure)
)
select * from compared
where previous is distinct from current
