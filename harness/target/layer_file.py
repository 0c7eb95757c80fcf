"""The schema of a layer.toml (harness/target/layer_description.py reads it): a pydantic model
per table, so that a refusal names the file, line, key and value (harness/schema.py)."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import ConfigDict, Field, model_validator

from harness.schema import Strict, accepted
from harness.target.domains import VIOLATIONS, Bounds

REJECTING = ("requires_init", "requires", "rejects_while")
CHECKING = ("checks_args", "narrows_while")  # argument checks, made before the rejecting ones
INTERRUPTING = ("interrupts", "excludes")
DEFECT_KINDS = {"interrupts_on_init": "reply", "deadlock_on_start": "protection", "leak_during_init": "protection"}

SERVICES_HINT = 'give a table of "module.Service" = ["module.Service", ...]'
Names = list[str]


class LayerTable(Strict):
    model_config = ConfigDict(title="[layer]")
    doc: str = ""
    behaviour: str | None = Field(None, description="give the name of an importable Python module that "
                                                    "provides build(env, world_file)")
    slots: int = Field(3, ge=1, description="give a whole number of activities >= 1")
    invalid_args: str = Field(description="give the reply code it answers invalid arguments with")
    no_slot: str = Field(description="give the reply code it answers when no activity slot is free")
    stop: str | None = Field(None, description="give the name of the service that stops its module")
    default_suts: Names | None = Field(None, min_length=1, description="give a non-empty list of variant names "
                                       "(a campaign's --sut when none is given), or leave it out for all variants")


class TimingTable(Strict):
    model_config = ConfigDict(title="a timing")
    start_s: float = Field(0.0, ge=0, description="give a number of seconds >= 0")
    run_s: float | Literal["forever"] = Field(description='give a number of seconds >= 0 or "forever"')

    @model_validator(mode="after")
    def _not_negative(self):
        if self.run_s != "forever" and self.run_s < 0:
            raise ValueError(f"run_s = {self.run_s!r}; give a number of seconds >= 0 or \"forever\"")
        return self


PROTECTION_KINDS = CHECKING + REJECTING + INTERRUPTING


class ProtectionTable(Strict):
    model_config = ConfigDict(title="a protection")
    kind: Literal[PROTECTION_KINDS] = Field(description=f"use one of {', '.join(PROTECTION_KINDS)}")
    reply: str | None = Field(None, description="give the reply code it answers with")
    checks: list[Literal[VIOLATIONS]] = Field(list(VIOLATIONS), description=f"give some of {', '.join(VIOLATIONS)}")
    domain: dict[str, Bounds] = Field(default_factory=dict, description="give argument = { min, max, choices, "
                                                                        "pattern } tables")
    after: dict[str, Names] = Field(default_factory=dict, description=SERVICES_HINT)
    while_: dict[str, Names] = Field(default_factory=dict, alias="while", description=SERVICES_HINT)
    by: dict[str, Names] = Field(default_factory=dict, description=SERVICES_HINT)
    pairs: list[Annotated[Names, Field(min_length=2, max_length=2)]] = Field(
        default_factory=list, description='give a list of ["module.Service", "module.Service"] pairs')
    stop: bool = False
    doc: str = ""


class DefectTable(Strict):
    model_config = ConfigDict(title="a defect")
    kind: Literal[tuple(DEFECT_KINDS)] = Field(description=f"use one of {', '.join(DEFECT_KINDS)}")
    reply: str | None = Field(None, description="give the reply code it answers with")
    protection: str | None = Field(None, description="give the name of a protection")
    doc: str = ""


class VariantTable(Strict):
    model_config = ConfigDict(title="a variant")
    protections: Names = []
    defects: Names = []
    doc: str = ""


class LayerFile(Strict):
    model_config = ConfigDict(title="a layer description")
    layer: LayerTable
    timing: dict[str, TimingTable] = {}
    protections: dict[str, ProtectionTable] = {}
    defects: dict[str, DefectTable] = {}
    variants: dict[str, VariantTable] = Field(min_length=1, description="add [variants.NAME] tables "
                                                                       "(protections, defects, doc)")


LAYER_KEYS = set(accepted(LayerTable))  # the keys of [layer] (docs/reference names every one)
