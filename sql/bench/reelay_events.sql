-- bench/reelay_bench.py: every event in trace order, as the propositions of PRE(ndd.GotoPosition)
-- in reelay's past-time MTL: the trace's first event, a GotoPosition request, an ok final reply
-- to SetParams.
select row_number() over (partition by trace_id order by t, seq) = 1 as start,
       kind = 'request' and module = 'ndd' and service = 'GotoPosition' as goto,
       kind = 'final' and module = 'ndd' and service = 'SetParams' and reply = 'ok' as setparams_ok
from events
order by trace_id, t, seq
