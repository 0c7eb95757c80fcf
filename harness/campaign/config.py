"""A campaign's identity: the config its arguments make (stored in campaigns.config), checked
before anything runs, and the stored campaign that a rerun with the same arguments resumes."""
from __future__ import annotations

import sys

from harness.campaign import sharding
from harness.campaign.budget import parse_duration
from harness.campaign.request import CampaignRequest
from harness.errors import StoreError, UntimelyError
from harness.mutator import strategies
from harness.mutator.script_time import least_s
from harness.mutator.operators import chosen as chosen_operators
from harness.dispatch import cluster
from harness.store.record import CampaignRecord, records
from harness.sut.definitions import resolve
from harness.target.mission import Mission
from harness.target.script import Script

# Arguments that decide what is run; --jobs, --cluster and --db do not.
COMPARED = ("mutants", "strategy", "sut", "external", "seed", "ops_per_mutant", "time_mutations", "operators",
            "value_mutations", "max_delay", "budget_s", "files", "shard")
# A store of ~300,000 traces, judged in a few GB of memory; generating them takes minutes.
MAX_MUTANTS = 100_000


def campaign_config(args: CampaignRequest, mission: Mission, golden: Script) -> CampaignRecord:
    """The campaign's identity (stored in campaigns.config) on the mission of `args.mission`, loaded,
    and its golden script; refuses arguments that make no sense together (each flag's own range is
    checked once, by the command line)."""
    if not 0 <= args.mutants <= MAX_MUTANTS:
        raise UntimelyError(f"--mutants {args.mutants}: give a number of mutants from 0 to {MAX_MUTANTS:,}; "
                            "split a larger study into campaigns of other --seed values")
    ops_per_mutant = strategies.operations(args.strategy, args.ops_per_mutant, args.time_mutations, args.operators)
    named = None if args.operators is None else list(chosen_operators(args.operators, args.time_mutations,
                                                                          args.value_mutations))
    if ops_per_mutant < 1:
        raise UntimelyError(f"--ops-per-mutant {ops_per_mutant}: give at least 1 operation per mutant")
    suts, external = resolve(args.sut or mission.default_suts(), mission.folder, args.time_scale)
    if mission.simulated and set(suts) - set(external):  # variants: a bad behaviour fails here, not in every run
        mission.layer.behaviour_module()
    given = args.budget
    if given is not None and args.strategy != "focused":
        raise UntimelyError(f"--budget {given} applies to --strategy focused, whose tests are made as "
                            f"the campaign goes; a {args.strategy} campaign runs its --mutants")
    if args.shard is not None and args.strategy == "focused":
        raise UntimelyError(f"--shard {args.shard} applies to random and targeted campaigns, whose runs are known "
                            "before they start; a focused campaign chooses its next tests from what the last ones "
                            "found: run it whole, without --shard")
    budget = {} if given is None else {"budget_s": _budget(given, golden, len(suts))}
    return CampaignRecord(**budget, mission=str(mission.folder.resolve()), mutants=args.mutants, sut=suts,
                          external=external,
                          strategy=args.strategy, seed=args.seed, ops_per_mutant=ops_per_mutant,
                          time_mutations=args.time_mutations, operators=named,
                          value_mutations=args.value_mutations,
                          max_delay=args.max_delay, jobs=args.jobs, files=mission.hashes(),
                          shard=sharding.parse(args.shard), code_identity=cluster.code_identity())


def _budget(given: str, golden, variants: int) -> float:
    """--budget in seconds; refused when the golden runs alone, which every focused campaign makes
    first, outlast it (their sleeps are a lower bound of their mission time)."""
    seconds, least = parse_duration(given), variants * least_s(golden)
    if seconds < least:
        raise UntimelyError(f"--budget {given}: the golden script's runs alone, on {variants} variant(s), take at "
                            f"least {least:g} mission s (its sleeps); give a budget of more than {least:g}s")
    return seconds


def _difference(stored: CampaignRecord, wanted: CampaignRecord) -> str | None:
    for key in COMPARED:
        if key == "files":  # a campaign stored before a file was hashed compares those it hashed
            changed = [n for n in stored.files if stored.files[n] != wanted.files.get(n)]
            if not changed:
                continue
            return f"--mission {stored.mission} had other contents: {', '.join(changed)} differ from {wanted.mission}"
        theirs, ours = _compared(stored, key), _compared(wanted, key)
        if theirs == ours:
            continue
        if key == "external":
            return f"external SUTs {theirs}, not {ours}"
        listed = lambda v: ",".join(v) if v else "(the default)"  # noqa: E731
        show = {"sut": listed, "operators": listed, "budget_s": lambda v: "none" if v is None else f"{v:g}s"}.get(key, str)
        flag = "--budget" if key == "budget_s" else "--" + key.replace("_", "-")
        return f"{flag} {show(theirs)}, not {show(ours)}"
    return None


def _compared(record: CampaignRecord, key: str):
    """A key's value as two campaigns are told apart by: an external SUT by the fields its record
    stores (one stored before a field existed lacks it, and is not the SUT the field's default makes)."""
    return record.stored().get("external", {}) if key == "external" else getattr(record, key)


def _code_change(campaign_id: int, stored: CampaignRecord, wanted: CampaignRecord, db, allowed: bool) -> None:
    """A campaign resumed by other code than made it would mix the traces of two benches (of two
    simulators, say): refused unless `allowed`, and then said. A campaign stored before code
    identities were recorded has none to compare."""
    if stored.code_identity is None or stored.code_identity == wanted.code_identity:
        return
    shown = lambda c: f"version {c.get('version')}, code {c.get('code')}"  # noqa: E731
    change = (f"{db} holds campaign {campaign_id}, made by the bench at {shown(stored.code_identity)}; "
              f"this bench is at {shown(wanted.code_identity)}")
    if not allowed:
        raise StoreError(f"{change}: its traces would mix runs of two codes. Run the code that made it to "
                         "resume it, or pass another --db for a new campaign, or --allow-code-change to resume "
                         "it anyway")
    print(f"{change}; resuming it anyway (--allow-code-change): its traces mix runs of both", file=sys.stderr)


def find_campaign(con, config: CampaignRecord, db, allow_code_change: bool = False) -> int | None:
    """The store's campaign if it is this one; a campaign with other arguments, or made by other
    code (unless `allow_code_change`), is refused."""
    for campaign_id, _, stored in records(con, CampaignRecord):  # not an ad-hoc `run` sharing the store
        difference = _difference(stored, config)
        if difference:
            raise StoreError(f"{db} holds campaign {campaign_id}, made with {difference}; rerun with its "
                             "arguments to resume it, or pass another --db for a new campaign")
        _code_change(campaign_id, stored, config, db, allow_code_change)
        return campaign_id
    return None
