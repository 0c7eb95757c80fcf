-- Tables II-IV as one list of values per variant, family and measure, so that two analyses can
-- be compared cell by cell (table_changes). Table II is over all families: family 'All'.
create or replace view table_values as
select sut, 'All' as family, 'II' as paper_table, measure, value
from (select sut, with_fn::double as with_fn, with_fp::double as with_fp, bad::double as bad, t_rob
      from trace_robustness)
unpivot (value for measure in (with_fn, with_fp, bad, t_rob))
union all
select sut, family, 'III', 'tp_rate', tp_rate from tp_rates
union all
select sut, family, 'IV', 'fp_rate', fp_rate from fp_rates
