-- Paper Table IV: false positive rate = FP / (FP + TN) per variant and family (and All), with
-- n = FP + TN and its 95% Wilson interval (fp_rate_low, fp_rate_high: the sampling error); NULL
-- when no request of the family was judged TN or FP.
-- fp_rate_min and fp_rate_max: the lowest and highest rate over every choice of each verdict among
-- itself and its alternatives, computed as tp_rates computes its own, FP in the place of TP and TN
-- in the place of FN.
create or replace view fp_rates as
select sut, family, fp, tn, fp / nullif(fp + tn, 0) as fp_rate,
       fp + tn as n, wilson_low(fp, fp + tn) as fp_rate_low, wilson_high(fp, fp + tn) as fp_rate_high,
       case when fp_must + tn_can > 0 then fp_must / (fp_must + tn_can)
            when fp_can > 0 then 1.0 end as fp_rate_min,
       case when fp_can > 0 then fp_can / (fp_can + tn_must)
            when tn_can > 0 then 0.0 end as fp_rate_max
from family_verdicts
