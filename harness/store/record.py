"""What one row of `campaigns` records in its `config` column: a typed record per kind of campaign
(a campaign, an ad-hoc `run`, a shrink, an import), and the only Python that writes or reads it.

A kind of campaign is a subclass of `Record` with its own `kind` literal: defining it registers
it (`KINDS`), and `record_of` reads it from then on (tests/store/test_record.py adds a toy kind).

A key that a store written before it existed lacks reads as the field's default (a campaign made
before --strategy is a random one), so older stores read as they always did; a record is written
with the keys it was made or read with and no others, so a record read and written back (merge)
is stored as it was (an external SUT's definition too: its fields as given, nested). SQL reads the same JSON keys (sql/views/trace_scope.sql, the shrinks of
sql/report/_shrinks.sql).
"""
from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path
from typing import Annotated, ClassVar, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, ValidationError

from harness.errors import StoreError
from harness.schema import cut
from harness.target.suts import ExternalSut

DEFAULT_MAX_DELAY_S = 0.003  # of a run stored before the max delay was recorded


class Record(BaseModel):
    """The base of every kind of record; a subclass with a `kind: Literal[...]` field is a new kind."""
    # extra keys ignored: a store written by a later bench, with a key this one does not know, still reads
    model_config = ConfigDict(frozen=True, extra="ignore")
    KINDS: ClassVar[dict[str, type[Record]]] = {}

    @classmethod
    def __pydantic_init_subclass__(cls, **kwargs) -> None:
        super().__pydantic_init_subclass__(**kwargs)
        if "kind" not in cls.model_fields:  # a base of kinds, not a kind
            return
        kind = cls.model_fields["kind"].default
        if Record.KINDS.setdefault(kind, cls) is not cls:
            owner = Record.KINDS[kind].__qualname__
            raise TypeError(f"{cls.__qualname__}: kind {kind!r} is {owner}'s already; give it a kind of its own")

    def stored(self) -> dict:
        """The JSON object stored in campaigns.config: its kind and the keys it was given."""
        return {"kind": self.kind, **self.model_dump(mode="json", by_alias=True, exclude_unset=True)}

    def target(self, mission: str) -> Path:
        """The target folder the campaign was made from, given its `mission` column: that folder,
        or the folder of the file it names (a script, an imported file)."""
        return Path(mission) if Path(mission).is_dir() else Path(mission).parent


class CampaignRecord(Record):
    """`untimely campaign`: the arguments that decide what runs (harness.campaign.config)."""
    kind: Literal["campaign"] = "campaign"
    mission: str
    mutants: int
    sut: list[str]
    external: dict[str, ExternalSut] = {}  # by name; stored with the fields it was given (read)
    strategy: str = "random"
    seed: int
    ops_per_mutant: int
    time_mutations: bool = False
    operators: list[str] | None = None
    value_mutations: bool = False
    max_delay: float = DEFAULT_MAX_DELAY_S
    jobs: int = 0
    files: dict[str, str | None] = {}  # mission file name -> SHA-256 (None: the mission has no such file)
    shard: list[int] | None = None  # [I, N] of --shard I/N
    budget_s: float | None = None
    code_identity: dict[str, str] | None = None  # the bench's version and code hash; None: stored before it was

    def target(self, mission: str) -> Path:
        return Path(mission)


class RunRecord(Record):
    """`untimely run`: one script on one variant."""
    kind: Literal["run"] = "run"
    sut: str
    max_delay: float = DEFAULT_MAX_DELAY_S
    target_folder: str | None = Field(None, alias="target")  # None: stored before runs recorded it
    external: dict[str, ExternalSut] = {}  # its SUT, if external

    def target(self, mission: str) -> Path:
        return Path(self.target_folder) if self.target_folder else super().target(mission)


class ShrinkRecord(Record):
    """A shrink of one stored trace: the one record of what was shrunk, and how far it came."""
    kind: Literal["shrink"] = "shrink"
    op: Literal["shrink"] = "shrink"
    max_delay: float = DEFAULT_MAX_DELAY_S
    trace: int
    sut: str
    seed: int
    verdict: str  # FN, FP or hung
    property: str | None = None
    steps_before: int
    steps_after: int | None = None  # None: no shrunk script came out
    runs: int
    interrupted: bool = False  # stopped by Ctrl-C or a signal: a resumed campaign tries it again
    budget_spent: bool = False  # its campaign's budget ran out first: steps_after is the smallest shown by then


class ImportRecord(Record):
    """`untimely import`: traces read from a file or bag."""
    kind: Literal["import"] = "import"
    imported: str
    interface: str | None = None
    sha256: str

    def target(self, mission: str) -> Path:
        return Path(self.interface).parent if self.interface else super().target(mission)


@lru_cache(maxsize=None)
def _reader(kinds: tuple[type[Record], ...]) -> TypeAdapter:
    return TypeAdapter(Annotated[Union[kinds], Field(discriminator="kind")])


def record_of(config: dict | str, campaign_id: int | None = None) -> Record:
    """The record a stored config (JSON text or its object) holds; a config no bench wrote is refused."""
    try:
        reader = _reader(tuple(Record.KINDS.values()))
        return reader.validate_python(json.loads(config) if isinstance(config, str) else config)
    except (ValidationError, ValueError) as e:
        which = f"campaign {campaign_id}'s" if campaign_id is not None else "a campaign's"
        raise StoreError(f"{which} config {cut(config)} is not a record this bench reads ({_first_error(e)}): "
                         f"its kind must be one of {', '.join(Record.KINDS)} with their keys "
                         "(docs/reference/store.md); was the store written by another program?") from None


def _first_error(e: Exception) -> str:
    if isinstance(e, ValidationError):
        first = e.errors()[0]
        if first["type"] == "union_tag_not_found":
            return "it has no kind"
        if first["type"] == "union_tag_invalid":
            return f"kind {first['input'].get('kind')!r}"
        return f"{'.'.join(map(str, first['loc']))} = {cut(first['input'])}: {first['msg']}"
    return str(e)


def stored_json(record: Record) -> str:
    """The text of campaigns.config for `record`."""
    return json.dumps(record.stored(), sort_keys=True)


def records(con, kind: type[Record] | None = None) -> list[tuple[int, str, Record]]:
    """(campaign_id, mission, record) of every stored campaign (of class `kind` if given), by id."""
    found = [(i, mission, record_of(config, i)) for i, mission, config in
             con.execute("select campaign_id, mission, config from campaigns order by campaign_id").fetchall()]
    return [row for row in found if kind is None or isinstance(row[2], kind)]
