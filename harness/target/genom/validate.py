"""What a service's `validate` codel states (genom3: it runs when a request arrives, before the
service starts, and an exception it throws rejects the request; the template's `after`/`before`
checks come first, with `disallowed`).

- The validate codel's parameters that name the service's own parameters (`local in speed`, or an
  unqualified name equal to one of them) are the arguments it checks: each one the bench can carry
  (a number or a string) goes into interface.toml's `args`, of its type and without bounds (the
  bounds are in the codel's C code), and the golden mission sends its default value;
- when that codel is the service's only codel and the service throws one exception, it is the
  rejection: `VAL(S)`, r_p that exception (class R: only validate codels throw it);
- its other parameters read the component's state (ids members, ports): it may reject a request
  that came too early; after which service, only an `after`/`before` clause says (PRE, PEX):
  without one, a note says so and nothing is guessed.
Each case that derives nothing says why in init's notes.
"""
from __future__ import annotations

from harness.target.domains import EMPTY_TEXT
from harness.target.draft import Draft, DraftArg, val
from harness.target.genom.reader import GenomScope, GenomService


def _word(param) -> str:
    """The word the golden mission sends: the default value when a script can write it as one word."""
    word = param.default
    if word is None or word == "" or any(c.isspace() or c == "#" for c in word):
        return "0" if param.type == "float" else EMPTY_TEXT
    return word


def _rejection(s: GenomService, draft: Draft, where: str) -> str | None:
    """The exception the validate codel of s rejects with, or None (and a note saying why)."""
    codes = s.listed("throws")
    if s.codels and codes:
        return None  # its exceptions may end the service too: the note of derive._exceptions says so
    why = None
    if not codes:
        why = "the service throws no exception of its own, so the codel cannot reject: it only checks or adjusts"
    elif len(codes) > 1:
        why = f"it may reject with any of {', '.join(codes)}: a VAL property names one; write it by hand"
    elif draft.replies.get(codes[0], ("T",))[0] != "R":
        why = f"{codes[0]} also ends other services (class T in the catalogue), so it cannot name a rejection"
    if why:
        draft.notes.append(f"{where}: {why}; no property derived from it")
        return None
    return codes[0]


def _arguments(s: GenomService, draft: Draft, where: str) -> dict[str, DraftArg]:
    checked = [p for p in s.params if any(k.local(s.params) and k.name == p.name for k in s.checks)]
    carried = {p.name: DraftArg(p.type, _word(p), p.doc) for p in checked if p.type}
    for p in checked:
        if not p.type:
            draft.notes.append(f"{where} checks `{p.written}`, a struct, array or named type (or an ids member "
                               "without a default value) that a mission cannot carry: not in interface.toml")
    return carried


def validated(c: GenomScope, services: dict[str, GenomService], draft: Draft) -> None:
    """The VAL properties and the arguments the validate codels state, notes for what they do not."""
    for s in (s for s in services.values() if s.validate):
        where = f"{s.lines['validate']}: {c.name}.{s.name} validate {s.validate}"
        state = [k.name for k in s.checks if not k.local(s.params) and k.direction != "out"]
        reply = _rejection(s, draft, where)
        if reply is None:
            continue
        if state and not (s.listed("after") or any(s.name in o.listed("before") for o in services.values())):
            draft.notes.append(f"{where} reads the component's state ({', '.join(state)}): it may reject a request "
                               f"that came too early with {reply}, but no after or before clause says after which "
                               "service: add a PRE property by hand if one must come first")
        args = _arguments(s, draft, where)
        if args:
            x = f"{c.name}.{s.name}"
            draft.args[x] = args
            cites = (f"{where}({', '.join(args)})", f"{s.lines['throws']}: {x} throw {reply}")
            draft.properties.append(val(x, reply, list(args), cites))
            draft.notes.append(f"{x}: the bounds its validate codel checks are in its C code, not in the .gen file: "
                               f"add min/max/choices to the args of interface.toml, else a value of the right type "
                               f"that the codel refuses is judged FP by VAL({x})")
