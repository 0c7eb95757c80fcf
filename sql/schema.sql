-- The trace store (docs/reference/store.md). Column names are a contract: add, never rename.
-- Identifiers are integers so that joins over millions of events stay fast.

create table if not exists campaigns (
    campaign_id  integer primary key,
    created_at   timestamp not null,
    mission      varchar not null,
    seed         bigint not null,
    config       json not null
);

create table if not exists scripts (
    script_id      integer primary key,
    campaign_id    integer not null,
    kind           varchar not null check (kind in ('golden', 'mutant', 'shrunk')),
    parent         integer,             -- script_id of the script it was mutated or shrunk from
    mutations      json not null,       -- list of operations, empty for golden
    body           varchar not null,    -- the script text as run
    valid          boolean not null,
    invalid_reason varchar              -- the validator's message when not valid
);

create table if not exists traces (
    trace_id     integer primary key,
    campaign_id  integer not null,
    script_id    integer,               -- null for imported traces
    sut          varchar not null,
    seed         bigint,
    outcome      varchar not null check (outcome in ('completed', 'hung', 'crashed')),
    sim_s        double,
    wall_s       double,
    error        varchar,               -- the exception of a crashed run
    label        varchar                -- the trace's own name in an imported file
);

-- Observed at the interface: the only table the oracles read.
create table if not exists events (
    trace_id  integer not null,
    seq       integer not null,
    t         double not null,
    kind      varchar not null check (kind in ('request', 'intermediate', 'final')),
    rqst_id   integer not null,
    module    varchar not null,
    service   varchar not null,
    args      json,
    reply     varchar
);

-- Simulator ground truth: the same events on the layer's internal clock. Never read by oracles.
create table if not exists internal_events (
    trace_id  integer not null,
    seq       integer not null,
    t         double not null,
    kind      varchar not null check (kind in ('request', 'intermediate', 'final')),
    rqst_id   integer not null,
    module    varchar not null,
    service   varchar not null,
    args      json,
    reply     varchar
);

-- Observed at the interface too: when the SUT replied that it took a request (protocol untimely/1,
-- reply kind `taken`, an optional interface extension). The oracles place such a request at this
-- instant instead of its sending. seq is on the counter of the trace's events (which skip it).
create table if not exists taken_events (
    trace_id  integer not null,
    seq       integer not null,
    t         double not null,
    rqst_id   integer not null
);

create table if not exists reply_codes (
    module   varchar not null,
    service  varchar not null,
    reply    varchar not null,
    class    varchar not null check (class in ('T', 'Z', 'R')),
    primary key (module, service, reply)
);

-- Simulator ground truth: collisions, driving with the antenna deployed, broken links.
create table if not exists world_events (
    trace_id  integer not null,
    t         double not null,
    kind      varchar not null,
    detail    json
);

-- Where, when and how fast a real-time run against an external SUT ran (docs/reference/protocol.md): such runs
-- are not reproducible, so their circumstances are kept. rtt_* are the liveness pings' round
-- trips in wall seconds (times time_scale for mission seconds); none for simulated runs.
-- transport_max_s: the largest round trip less what the SUT held its pong for (`held_s`: a ROS 2
-- adapter waits for the node's executor), the transport alone; null in runs stored before it was kept.
create table if not exists trace_runs (
    trace_id    integer primary key,
    host        varchar not null,
    started_at  timestamp not null,      -- UTC
    time_scale  double not null,
    sut_info    varchar,                 -- what the SUT said of itself in its hello
    pings       integer not null,
    rtt_p50_s   double,
    rtt_p95_s   double,
    rtt_max_s   double,
    transport_max_s double
);
alter table trace_runs add column if not exists transport_max_s double;  -- a store from before it

-- The schema versions this store went through (harness.store.SCHEMA_VERSION): created or migrated;
-- and which versions of Untimely wrote it.
create table if not exists schema_version (
    version     integer not null,
    applied_at  timestamp not null,
    note        varchar not null
);
-- The version of Untimely that created, migrated or first wrote the store in that layout
-- (a row whenever another version writes it).
alter table schema_version add column if not exists untimely varchar;

-- Every analysis: when, with which epsilon, over how many traces, and how long it took.
create table if not exists analyses (
    analysis_id  integer primary key,
    analysed_at  timestamp not null,
    epsilon      double not null,
    properties   integer not null,       -- how many properties were judged
    traces       integer not null,       -- how many traces the verdicts cover
    seconds      double not null         -- how long the analysis took
);

-- The files each analysis was made from, with their SHA-256 (provenance).
create table if not exists analysis_files (
    analysis_id  integer not null,
    role         varchar not null check (role in ('properties', 'interface', 'template')),
    path         varchar not null,
    sha256       varchar not null
);

-- The order of the variants: the order in which a campaign (or run, or import) first stored
-- them. Tables and the report list variants in it (schema version 3).
create table if not exists variant_positions (
    sut       varchar primary key,
    position  integer not null
);

-- The order of the modules in the interface description: trace timelines list them in it
-- (schema version 3).
create table if not exists module_positions (
    module    varchar primary key,
    position  integer not null
);

-- The oracles that failed in an analysis (docs/reference/verdicts.md): their property's verdicts are 'unknown',
-- every other property is judged as usual. `source` is the events table the oracle read.
create table if not exists oracle_failures (
    analysis_id  integer not null,
    property_id  varchar not null,
    source       varchar not null,
    template     varchar not null,
    error        varchar not null
);

-- The shrinks that failed (`campaign --shrink` goes on with the other behaviours): which
-- behaviour of which trace, and why.
create table if not exists shrink_failures (
    trace_id     integer not null,
    sut          varchar not null,
    verdict      varchar not null,       -- FN, FP or hung
    property_id  varchar,                -- none for a hang
    error        varchar not null,
    failed_at    timestamp not null      -- UTC
);

-- A campaign run under a budget or a stopping rule (--strategy focused, issue 21): its budget in
-- mission seconds (null: none), its stopping rule, the mission seconds of its shrink runs (the
-- traces hold the others), how many tests it has made, and why it stopped (rule, budget or
-- tests; null while it runs).
create table if not exists campaign_budgets (
    campaign_id  integer primary key,
    budget_s     double,
    rule         varchar not null,
    shrink_s     double not null,
    tests        integer not null,
    stopped      varchar
);

-- The runs of shrinks (issue 21): every candidate script a shrink ran is a trace of its own
-- (traces, events, ... with its mission seconds in traces.sim_s, in the shrink's campaign, of kind
-- "shrink"), and this row says which trace's bad behaviour it was shrinking and what it ran.
-- Tables II-IV, the findings and the rates leave these traces out (views trace_scope and
-- trace_findings); they get verdicts like any trace.
create table if not exists shrink_runs (
    trace_id  integer primary key,
    original  integer not null,          -- the trace whose script it shrinks
    body      varchar not null           -- the candidate script it ran
);
