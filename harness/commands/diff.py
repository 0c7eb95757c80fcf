"""`untimely diff`: what the last analysis changed."""
from __future__ import annotations

from dataclasses import dataclass

from harness.analysis import diff
from harness.commands import options

NAME = "diff"
HELP = "what the last analysis changed: verdict transitions, Tables II-IV"


@dataclass(frozen=True)
class DiffRequest:
    db: str = options.DEFAULT_DB_TEXT


Request = DiffRequest


def arguments(c) -> None:
    options.db(c)


def execute(request: DiffRequest) -> int:
    return diff.main(request.db)
