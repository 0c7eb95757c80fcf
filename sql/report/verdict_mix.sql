-- Per variant, its verdicts of every kind over all families (view family_verdicts).
select * from family_verdicts
where family = 'All'
