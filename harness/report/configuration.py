"""The configuration the report shows of a campaign: what its strategy used. A focused campaign
makes its tests as it goes (docs/campaign.md): `--mutants` only caps them, and the random
strategy's operators, operations per mutant and time mutations it never reads; it shows the tests
it made and why it stopped instead, and the cap only where the cap is what stopped it."""
from __future__ import annotations

UNUSED_BY_FOCUSED = ("mutants", "operators", "ops_per_mutant", "time_mutations", "shard")


def shown(config: dict, budget: dict | None) -> dict:
    """`config` (a campaigns.config) as the report shows it; `budget`: the campaign's campaign_budgets
    row (tests, stopped), None where it has none."""
    if config.get("strategy") != "focused":
        return config
    kept = {key: value for key, value in config.items() if key not in UNUSED_BY_FOCUSED}
    if budget is None:  # stopped before its first round was recorded
        return kept
    kept["tests"] = budget["tests"]
    kept["stopped"] = budget["stopped"] or "not yet (running, or stopped before the end: resume it)"
    if budget["stopped"] == "tests":
        kept["tests at most (--mutants)"] = config["mutants"]
    return kept
