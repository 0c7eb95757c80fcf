-- Paper Table III: true positive rate = TP / (TP + FN) per variant and family (and All), with
-- n = TP + FN and its 95% Wilson interval; NULL when no request of the family needed enforcement.
create or replace view tp_rates as
select sut, family, tp, fn, tp / nullif(tp + fn, 0) as tp_rate,
       tp + fn as n, wilson_low(tp, tp + fn) as tp_rate_low, wilson_high(tp, tp + fn) as tp_rate_high
from family_verdicts
