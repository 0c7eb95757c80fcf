-- The 95% Wilson score interval of a proportion of k cases out of n: the one definition of
-- every rate's interval (Tables III-IV, coverage). NULL when n = 0. z = 1.96 (two-sided 95%);
-- clamped to [0, 1] against rounding at k = 0 and k = n.
create or replace macro wilson_low(k, n) as
    case when n > 0 then greatest(0.0,
        (k / n + 1.96 ^ 2 / (2 * n) - 1.96 * sqrt(k / n * (1 - k / n) / n + 1.96 ^ 2 / (4 * n ^ 2)))
        / (1 + 1.96 ^ 2 / n))
    end;

create or replace macro wilson_high(k, n) as
    case when n > 0 then least(1.0,
        (k / n + 1.96 ^ 2 / (2 * n) + 1.96 * sqrt(k / n * (1 - k / n) / n + 1.96 ^ 2 / (4 * n ^ 2)))
        / (1 + 1.96 ^ 2 / n))
    end;
