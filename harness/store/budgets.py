"""Writing a focused campaign's budget, stopping rule and why it stopped (table campaign_budgets)."""
from __future__ import annotations


def record_budget(con, campaign_id: int, budget_s: float | None, rule: str, shrink_s: float, tests: int,
                  stopped: str | None) -> None:
    con.execute("insert or replace into campaign_budgets (campaign_id, budget_s, rule, shrink_s, tests, stopped) "
                "values (?, ?, ?, ?, ?, ?)", [campaign_id, budget_s, rule, shrink_s, tests, stopped])
