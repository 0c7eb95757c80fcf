{% import 'oracles/_epsilon.sql' as eps %}
-- Which epsilon each trace was judged with (sql/oracles/_epsilon.sql): the one its pings
-- measured (real-time runs), 0 where the SUT replied `taken` to every request, else the analysis's.
-- transport_epsilon_s: the one a deadline is judged with (the transport alone).
create or replace view trace_epsilon as
with {{ eps.per_trace() }}
select t.trace_id, t.sut, coalesce(e.epsilon, a.epsilon) as epsilon_s,
       coalesce(e.source, 'analysis') as source,
       coalesce(e.transport_epsilon, a.epsilon) as transport_epsilon_s  -- the deadlines'
from traces t cross join analysis a left join epsilons e using (trace_id)
