"""What each injected defect and missing protection of a simulated layer must show (issue 21).

Read from the target folder's layer.toml (the implementation's own knowledge, which a campaign
never reads) and its properties: a protection the layer knows but a variant lacks must show as
an FN on a property whose rejection or interruption code is that protection's reply; an
`interrupts_on_init` defect as an FP on a property whose interruption code is its reply; a
`deadlock_on_start` as a hang; a `leak_during_init` as an FN on a property with the leaking
protection's code. A missing argument check (checks_args, narrows_while) is left out: the timing defects are
what the bench's figures compare, and only campaigns with --value-mutations aim at argument
checks (tests/campaign/test_value_domains.py checks that they expose them).
A defect counts as exposed when the store's `findings` view holds such a
finding with a shrunk reproducer of at most MAX_STEPS steps.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from harness.target.interface import Property
from harness.target.mission import load_layer
from harness.target.layer_file import CHECKING
from harness.store.sql import render_bench

MAX_STEPS = 10


@dataclass(frozen=True)
class Expected:
    sut: str
    what: str  # "missing PRE", "defect init_interrupts"
    kind: str  # FN, FP or hung
    properties: frozenset[str]  # any of them will do; empty for a hang

    def matches(self, sut: str, property_id: str | None, kind: str) -> bool:
        return sut == self.sut and kind == self.kind and (property_id in self.properties or not self.properties)


def expected(folder: Path, properties: list[Property], suts: list[str]) -> list[Expected]:
    layer = load_layer(folder)

    def coded(code: str, z_only: bool = False) -> frozenset[str]:
        return frozenset(p.id for p in properties if p.z_p == code or (not z_only and p.r_p == code))
    found = []
    for sut in suts:
        variant = layer.variant(sut)
        kept = {p.name for p in variant.protections}
        for name, protection in layer.protections.items():
            if name not in kept and protection.kind not in CHECKING and coded(protection.reply):
                found.append(Expected(sut, f"missing {name}", "FN", coded(protection.reply)))
        for d in variant.defects:
            if d.kind == "interrupts_on_init":
                found.append(Expected(sut, f"defect {d.name}", "FP", coded(d.reply, z_only=True)))
            elif d.kind == "deadlock_on_start":
                found.append(Expected(sut, f"defect {d.name}", "hung", frozenset()))
            elif d.kind == "leak_during_init":
                found.append(Expected(sut, f"defect {d.name}", "FN", coded(layer.protections[d.protection].reply)))
    return found


def exposed(con, wanted: list[Expected]) -> dict[Expected, tuple[int, int] | None]:
    """Per expected finding: (its reproducer's script id, steps) if the store shows it shrunk to at
    most MAX_STEPS steps, else None."""
    rows = con.execute(render_bench("short_reproducers"), [MAX_STEPS]).fetchall()
    return {e: next(((r[3], r[4]) for r in rows if e.matches(*r[:3])), None) for e in wanted}
