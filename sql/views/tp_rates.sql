-- Paper Table III: true positive rate = TP / (TP + FN) per variant and family (and All), with
-- n = TP + FN and its 95% Wilson interval; NULL when no request of the family needed enforcement.
-- tp_rate_certain counts only the certain FNs (those no reordering of events closer than epsilon
-- could change): the rate if every possible FN were a false observation. The two bound the rate.
create or replace view tp_rates as
select sut, family, tp, fn, tp / nullif(tp + fn, 0) as tp_rate,
       tp + fn as n, wilson_low(tp, tp + fn) as tp_rate_low, wilson_high(tp, tp + fn) as tp_rate_high,
       fn_certain, tp / nullif(tp + fn_certain, 0) as tp_rate_certain
from family_verdicts
