"""Implementation variants of the simulated Dala layer: protections enforced, defects injected.

They mirror the paper's systems under test (DESIGN §3 table). Protections:

- PEX: an exec request of a module whose Init has not ended ok is rejected `wait_init`.
- AIB: an accepted dominating request interrupts the dominated running activities of its
  module (`interrupted`). Without it, a Stop still stops its module's activities, which then end
  `ok` (nothing signals the interruption), and a second activity of the same type runs beside
  the first.
- PRE: an exec request whose required services have not all ended ok is rejected `disallowed`.
- EXC: an accepted request interrupts the running activities it excludes, in any module
  (`interrupted_excl`): priority to the latest request.

Requests are checked in the order bad_params, PEX, PRE, free activity slot; only an accepted
request interrupts anything.

Defects:

- init_interrupts: every Init interrupts all running activities of its module (`interrupted`).
- deadlock_on_dominated_start: a dominating request that reaches an activity still in its start
  phase deadlocks the module: its control task stops answering, its activities fall silent, the
  liveness probe goes unanswered.
- pex_leak_during_init: exec requests arriving while the module's first Init is still running
  are accepted.
- deadlock_on_excluded_start: an exclusion (EXC) interrupting an activity still in its start
  phase deadlocks that activity's module (the rare interleaving of bip-b).
"""
from __future__ import annotations

from dataclasses import dataclass

from harness.errors import UntimelyError

PROTECTIONS = ("PEX", "AIB", "PRE", "EXC")

# Injected defects (see the module docstring).
INIT_INTERRUPTS = "init_interrupts"
DEADLOCK_ON_DOMINATED_START = "deadlock_on_dominated_start"
PEX_LEAK_DURING_INIT = "pex_leak_during_init"
DEADLOCK_ON_EXCLUDED_START = "deadlock_on_excluded_start"


@dataclass(frozen=True)
class Variant:
    protections: frozenset[str]
    defects: frozenset[str]
    doc: str

    def __repr__(self) -> str:
        return (f"<Variant protections={','.join(p for p in PROTECTIONS if p in self.protections) or '-'} "
                f"defects={','.join(sorted(self.defects)) or '-'}>")


def _variant(protections: str, defects: tuple[str, ...], doc: str) -> Variant:
    return Variant(frozenset(protections.split()), frozenset(defects), doc)


VARIANTS = {
    "genom": _variant("PEX AIB", (INIT_INTERRUPTS,),
                      "GenoM: PEX and AIB; the undocumented Init quirk makes its AIB false positives."),
    "bip-a": _variant("PEX AIB EXC", (DEADLOCK_ON_DOMINATED_START, PEX_LEAK_DURING_INIT),
                      "first BIP model: the PRE connector is missing; a dominating request during a "
                      "start phase deadlocks; PEX leaks while the first Init runs."),
    "bip-b": _variant("PEX AIB PRE EXC", (DEADLOCK_ON_EXCLUDED_START,),
                      "corrected BIP model: every protection; a rare deadlock when an exclusion hits "
                      "an activity in its start phase."),
    "bare": _variant("", (), "no protection at all: every violation is a false negative."),
    "reference": _variant("PEX AIB PRE EXC", (), "every protection, no defect."),
}


def variant_named(name: str) -> Variant:
    if name not in VARIANTS:
        raise UntimelyError(f"unknown variant {name!r}; choose one of {', '.join(VARIANTS)}")
    return VARIANTS[name]
