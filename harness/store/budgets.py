"""Writing a focused campaign's budget, stopping rule and why it stopped (table campaign_budgets)."""
from __future__ import annotations

from dataclasses import astuple, dataclass, fields


@dataclass(frozen=True)
class BudgetRow:
    """A row of campaign_budgets: its fields are the table's columns, in order."""
    campaign_id: int
    budget_s: float | None  # None: no budget, the stopping rule alone ends the campaign
    rule: str
    shrink_s: float
    tests: int
    stopped: str | None  # why it stopped; None while it runs


def record_budget(con, row: BudgetRow) -> None:
    columns = [f.name for f in fields(BudgetRow)]
    con.execute(f"insert or replace into campaign_budgets ({', '.join(columns)}) "
                f"values ({', '.join('?' * len(columns))})", list(astuple(row)))
