{#- The views a store analysed by an earlier bench lacks, as temporary views, so that the report
    reads it as it is. `missing`: the views it lacks. -#}
{% if 'trace_scope' in missing %}
-- analysed before trace_scope: its views counted every trace
create temp view trace_scope as
select trace_id, sut, campaign_id, true as counted, null::varchar as left_out
from traces;
{% endif %}
{% if 'trace_badness' in missing %}
-- analysed before trace_badness, and so before verdicts had alternatives: every verdict as observed
{% with temp = true %}{% include 'views/verdict_options.sql' %}{% endwith %};
{% with temp = true, alternatives = '[]::varchar[]' %}{% include 'views/trace_badness.sql' %}{% endwith %};
{% endif %}
{% if 'shrink_runs' in missing %}
-- written before shrink runs were stored: it holds none
create temp view shrink_runs as
select trace_id, trace_id as original, '' as body
from traces
where false;
{% endif %}
{% for name in ('trace_findings', 'findings') if name in missing %}
{% with temp = true %}{% include 'views/' ~ name ~ '.sql' %}{% endwith %};
{% endfor %}
