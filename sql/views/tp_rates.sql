-- Paper Table III: true positive rate = TP / (TP + FN) per variant and family (and All);
-- NULL when no request of the family needed enforcement.
create or replace view tp_rates as
select sut, family, tp, fn, tp / nullif(tp + fn, 0) as tp_rate
from family_verdicts
