-- The traces that get a page: the bad ones (hung, crashed, with an FN or FP, suspicious or not,
-- counted or not), those whose verdicts the observation delay inverted, and the runs of golden
-- and shrunk scripts. The others get one on demand (report --trace ID).
select trace_id from traces where outcome <> 'completed'
union select trace_id from verdicts where verdict in ('FN', 'FP')
union select trace_id from inversions
union select t.trace_id from traces t join scripts s using (script_id) where s.kind in ('golden', 'shrunk')
order by trace_id
