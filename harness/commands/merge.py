"""`untimely merge OUT STORE...`: the stores of a sharded campaign, combined and judged."""
from __future__ import annotations

from dataclasses import dataclass

from harness.campaign import sharding

NAME = "merge"
HELP = "combine the stores of a sharded campaign (campaign --shard I/N) into one"


@dataclass(frozen=True)
class MergeRequest:
    out: str
    stores: list[str]
    properties: str | None = None


Request = MergeRequest


def arguments(c) -> None:
    c.add_argument("out", help="the merged store, a new file")
    c.add_argument("stores", nargs="+", metavar="STORE", help="the shards' stores, one per part")
    c.add_argument("--properties", help="properties to judge the merged traces with (default: those of the "
                                        "shards' last analysis, else the campaign mission's)")


def execute(request: MergeRequest) -> int:
    return sharding.merge(request.out, request.stores, request.properties)
