"""How a campaign makes its mutants: the paper's random operators, or targeted ones.

`random` (the default) draws the paper's operators uniformly (with --time-mutations and
--value-mutations, those operators too): the verdict rates then describe
what random perturbations of the mission meet, as in the paper's Tables III-IV. `targeted` aims
every mutant at the least-covered property's P-condition (harness.mutator.targeted): far more
cases per property and more bad behaviours found, but its rates describe aimed cases, so they
are not comparable with the paper's. `focused` (harness.mutator.focused) makes short tests, one
per way to falsify each property's condition, then repeats of the timing-sensitive ones, as the
campaign goes: it answers "what is wrong with this layer", in the fewest mission seconds, and
stops by itself (harness.campaign.budgeted); its rates describe its tests only.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable, Iterator

from harness.errors import UntimelyError
from harness.target.interface import Interface, Property
from harness.target.mission import PROPERTIES_FILE
from harness.analysis.judge import Judge
from harness.mutator import focused, operators, targeted
from harness.mutator.operators import Mutant
from harness.mutator.timeline import ScriptTimeline
from harness.store.record import CampaignRecord
from harness.target.script import Script
from harness.trace import Trace

STRATEGIES = ("random", "targeted", "focused")
DEFAULT_OPERATIONS = {"random": 1, "targeted": targeted.SITES_PER_MUTANT, "focused": 1}


def operations(strategy: str, given: int | None, time_mutations: bool, named_operators: str | None = None) -> int:
    """Operations per mutant: the one given, or the strategy's default; refuses what does not apply."""
    if strategy not in STRATEGIES:
        raise UntimelyError(f"--strategy {strategy!r}: choose one of {', '.join(STRATEGIES)}")
    if strategy != "random" and time_mutations:
        raise UntimelyError(f"--time-mutations applies to --strategy random only; {strategy} mutants "
                            "choose their own sleeps")
    if strategy == "targeted" and named_operators is not None:
        raise UntimelyError("--operators applies to --strategy random only; targeted mutants insert "
                            "the requests that falsify conditions")
    if strategy == "focused" and given not in (None, 1):
        raise UntimelyError(f"--ops-per-mutant {given}: a focused test makes one perturbation; "
                            "leave the option out")
    return DEFAULT_OPERATIONS[strategy] if given is None else given


def plan(config: CampaignRecord, golden: Script, interface: Interface, properties: list[Property],
         golden_trace: Trace) -> focused.Plan:
    """A focused campaign's tests, made as the campaign goes (harness.campaign.budgeted). Without
    --value-mutations its tests replay golden values: a value-domain property is no aim of theirs."""
    timeline = ScriptTimeline(golden, golden_trace, interface.replies)
    return focused.Plan(golden, timeline, interface, _aimed(config, properties), config.seed,
                        str(Path(config.mission) / PROPERTIES_FILE))


def _aimed(config: CampaignRecord, properties: list[Property]) -> list[Property]:
    """The properties the targeted and focused strategies aim at: value-domain ones only when value
    mutations are asked for, so that a timing campaign's mutants stay as they were."""
    if config.value_mutations:
        return properties
    return [p for p in properties if p.type not in targeted.VALUE_TYPES]


def generate(config: CampaignRecord, golden: Script, interface: Interface, properties: list[Property],
             run_golden: Callable[[], Trace], name: Callable[[int], str]) -> list[Mutant]:
    """The campaign's mutants, all of them (mutants() gives them one at a time)."""
    return list(mutants(config, golden, interface, properties, run_golden, name))


def mutants(config: CampaignRecord, golden: Script, interface: Interface, properties: list[Property],
            run_golden: Callable[[], Trace], name: Callable[[int], str]) -> Iterator[Mutant]:
    """The campaign's mutants, as they are drawn (a campaign shows its progress); `run_golden` runs
    the golden on the campaign's first variant with that run's seed (targeted generation reads its
    timeline and verdicts)."""
    named, timed = config.operators, config.time_mutations
    draw = operators.Draw(config.mutants, config.seed, config.ops_per_mutant, timed,
                          tuple(named) if named else operators.chosen(None, timed, config.value_mutations))
    if config.strategy == "random":
        yield from operators.generate(golden, interface, draw, name)
        return
    properties = _aimed(config, properties)
    trace = run_golden()
    verdicts = Judge(interface, properties).verdicts([trace])[0]
    yield from targeted.generate(targeted.GoldenRun(golden, trace, verdicts), interface, properties, draw, name)
