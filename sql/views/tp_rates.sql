-- Paper Table III: true positive rate = TP / (TP + FN) per variant and family (and All), with
-- n = TP + FN and its 95% Wilson interval (tp_rate_low, tp_rate_high: the sampling error); NULL
-- when no request of the family needed enforcement.
-- tp_rate_min and tp_rate_max: the lowest and highest rate over every choice of each verdict among
-- itself and its alternatives (the orders of the events closer than epsilon), the denominator
-- moving with the numerator. A verdict adds (1, 1) as TP, (0, 1) as FN, (0, 0) as anything else, so
-- the extremes are greedy: lowest with every possible FN an FN and a TP only where it must be one;
-- highest with every possible TP a TP and an FN only where it must be one. A choice that leaves no
-- TP nor FN has no rate: the other extreme is then the only one (1 or 0), NULL when none has one.
create or replace view tp_rates as
select sut, family, tp, fn, tp / nullif(tp + fn, 0) as tp_rate,
       tp + fn as n, wilson_low(tp, tp + fn) as tp_rate_low, wilson_high(tp, tp + fn) as tp_rate_high,
       case when tp_must + fn_can > 0 then tp_must / (tp_must + fn_can)
            when tp_can > 0 then 1.0 end as tp_rate_min,
       case when tp_can > 0 then tp_can / (tp_can + fn_must)
            when fn_can > 0 then 0.0 end as tp_rate_max
from family_verdicts
