-- The last analysis: the one the stored verdicts come from.
create or replace view analysis as
select * from analyses
order by analysis_id desc
limit 1
