{#- What each shrink that came to a script shrank (its record in campaigns.config, kind "shrink":
    the one home of that fact, docs/reference/store.md), with the shrunk script. -#}
{% macro shrunk_scripts() -%}
select s.script_id, s.body, c.config->>'sut' as sut, c.config->>'verdict' as verdict,
           c.config->>'property' as property_id, (c.config->>'trace')::integer as trace_id,
           (c.config->>'steps_before')::integer as steps_before,
           (c.config->>'steps_after')::integer as steps_after, (c.config->>'runs')::integer as runs
    from campaigns c join scripts s on s.campaign_id = c.campaign_id and s.kind = 'shrunk'
    where c.config->>'kind' = 'shrink'
{%- endmacro %}
