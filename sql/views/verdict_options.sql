-- A verdict's options: the observed verdict and its alternatives, every verdict some ordering of the
-- events closer than epsilon could give. The one test of what a verdict could be and must be, read by
-- the counts behind the interval of every cell of Tables II-IV (property_verdicts, trace_badness).
-- `temp`: temporary macros, for a store analysed before they existed and read as it is.
create or replace {{ 'temp ' if temp | default(false) }}macro can_be(verdict, alternatives, kinds) as
    len(list_intersect(list_append(alternatives, verdict), kinds)) > 0;

-- Every option is among `kinds`: the verdict is one of them whatever the order was.
create or replace {{ 'temp ' if temp | default(false) }}macro must_be(verdict, alternatives, kinds) as
    len(list_filter(list_append(alternatives, verdict), lambda option: not list_contains(kinds, option))) = 0;
