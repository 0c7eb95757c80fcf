-- Paper Table IV: false positive rate = FP / (FP + TN) per variant and family (and All), with
-- n = FP + TN and its 95% Wilson interval; NULL when no request of the family was judged TN or FP.
create or replace view fp_rates as
select sut, family, fp, tn, fp / nullif(fp + tn, 0) as fp_rate,
       fp + tn as n, wilson_low(fp, fp + tn) as fp_rate_low, wilson_high(fp, fp + tn) as fp_rate_high
from family_verdicts
