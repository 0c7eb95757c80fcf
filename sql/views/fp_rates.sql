-- Paper Table IV: false positive rate = FP / (FP + TN) per variant and family (and All), with
-- n = FP + TN and its 95% Wilson interval; NULL when no request of the family was judged TN or FP.
-- fp_rate_certain counts only the certain FPs: the rate if every possible FP were a false
-- observation. The two bound the rate.
create or replace view fp_rates as
select sut, family, fp, tn, fp / nullif(fp + tn, 0) as fp_rate,
       fp + tn as n, wilson_low(fp, fp + tn) as fp_rate_low, wilson_high(fp, fp + tn) as fp_rate_high,
       fp_certain, fp_certain / nullif(fp_certain + tn, 0) as fp_rate_certain
from family_verdicts
