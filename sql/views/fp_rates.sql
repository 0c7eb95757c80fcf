-- Paper Table IV: false positive rate = FP / (FP + TN) per variant and family (and All);
-- NULL when no request of the family was judged TN or FP.
create or replace view fp_rates as
select sut, family, fp, tn, fp / nullif(fp + tn, 0) as fp_rate
from family_verdicts
