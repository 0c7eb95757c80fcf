"""What a focused campaign prints as it ends: why it stopped, and what it found (view findings)."""
from __future__ import annotations

from harness.campaign.budget import RULE
from harness.campaign.budgeted import PATIENCE, FocusedRun
from harness.store import campaign_reads
from harness.textable import format_table

def stopped_line(run: FocusedRun, reason: str) -> str:
    why = {"rule": "its stopping rule says nothing new is expected: "
                   + RULE.format(patience=PATIENCE),
           "budget": "the next test does not fit in the budget",
           "tests": f"it made --mutants {run.config.mutants} tests"}[reason]
    limit = "no budget" if run.budget.limit_s is None else f"budget {run.budget.limit_s:,.0f}"
    # every other run is admitted only if its bound fits: only the golden runs, made first, overrun it
    over = ("; the golden runs alone took more than the budget: give a larger --budget to a new --db"
            if run.budget.left() < 0 else "")
    return (f"stopped   ({reason}) {why}; spent {run.budget.spent_s:,.0f} mission s ({limit}), "
            f"of which shrinking {run.shrink_s:,.0f}{over}")


def findings_table(con) -> str:
    rows = campaign_reads.findings(con)
    if not rows:
        return "nothing went wrong"
    return format_table(["variant", "property", "kind", "first trace", "traces", "reproducer", "steps"], rows,
                        null="-")
