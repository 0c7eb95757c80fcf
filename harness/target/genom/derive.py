"""What `untimely init --from-genom FILE.gen` derives from a GenoM3 description (module = component),
following genom3's semantics of the clauses:
- `S after Q` (S cannot run until Q has ended ok once) and `B before S` (the same, written on B):
  the PC property PRE(S), q = those services, enforced by genom3's standard exception
  `disallowed`; the one service every other activity needs this way (if only one) is the init
  service: PEX(module);
- `S interrupts X` (`all`: every service): S is a dominator of the running activity X: AIB(X), EE,
  enforced by `interrupted`; genom3's standard `kill` interrupts all;
- exceptions: class R (a rejection) when only validate codels can throw them (every service that
  throws one has a validate codel and no other codel), class T (ended with it) otherwise;
- validate codels: the arguments they check and the VAL properties they state (validate.py).
Every property names, in a comment of properties.toml, the clauses and lines it comes from.
"""
from __future__ import annotations

from pathlib import Path

from harness.errors import InputFileError
from harness.target.draft import Draft, aib, pex, pre
from harness.target.genom.reader import GenomScope, provided, read_scopes
from harness.target.genom.validate import validated

STANDARD_REPLIES = {"too_many_activities": ("R", "genom3: no free instance of the activity (standard exception)")}
UNUSABLE = ("abort_activity", "connect_port", "connect_service")  # name middleware ids a mission cannot know


def _kind(service) -> str:
    return "exec" if service.kind == "activity" else "control"


def _cite(service, clause: str) -> str:
    if service.scope == "genom":
        return f"genom3's standard service {service.name} ({clause} {', '.join(service.listed(clause))})"
    return f"{service.lines[clause]}: {service.scope}.{service.name} {clause} {', '.join(service.listed(clause))}"


def _needs(c: GenomScope, services: dict, draft: Draft) -> dict[str, dict[str, list[str]]]:
    """service -> the services it needs an earlier ok of -> the clauses that say so."""
    needs: dict[str, dict[str, list[str]]] = {}
    for s in services.values():
        for clause in ("after", "before"):
            for named in s.listed(clause):
                if named not in services:
                    draft.notes.append(f"{c.name}.{s.name} ({s.lines[clause]}) {clause} {named!r}, which the "
                                       "component does not declare: left out")
                    continue
                x, q = (s.name, named) if clause == "after" else (named, s.name)
                cites = needs.setdefault(x, {}).setdefault(q, [])
                cites += [_cite(s, clause)] if _cite(s, clause) not in cites else []
    return needs


def _preconditions(c: GenomScope, services: dict, draft: Draft) -> None:
    needs = _needs(c, services, draft)
    activities = [s for s in services if services[s].kind == "activity"]
    needed = {q for first in needs.values() for q in first}
    common = sorted(q for q in needed if any(a != q for a in activities)
                    and all(q in needs.get(a, {}) for a in activities if a != q))
    if activities and len(common) == 1:  # several: none of them is *the* init service, each stays a PRE
        init = common[0]
        draft.modules[c.name][init] = "init"
        cites = [cite for a in activities if a != init for cite in needs[a].pop(init)]
        draft.properties.append(pex(draft, c.name, init, "disallowed", tuple(dict.fromkeys(cites))))
    for x, first in needs.items():
        if first:
            cites = tuple(dict.fromkeys(cite for q in first for cite in first[q]))
            draft.properties.append(pre(f"{c.name}.{x}", [f"{c.name}.{q}" for q in first], cites))


def _dominators(c: GenomScope, services: dict, draft: Draft) -> None:
    for x in (s for s in services if services[s].kind == "activity"):
        by = [s for s in services.values() if "all" in s.listed("interrupts") or x in s.listed("interrupts")]
        if by:
            draft.properties.append(aib(f"{c.name}.{x}", [f"{c.name}.{s.name}" for s in by],
                                        tuple(_cite(s, "interrupts") for s in by)))
    for s in services.values():
        for named in s.listed("interrupts"):
            if named != "all" and named not in services:
                draft.notes.append(f"{c.name}.{s.name} ({s.lines['interrupts']}) interrupts {named!r}, which the "
                                   "component does not declare: left out")


def _exceptions(c: GenomScope, services: dict, draft: Draft) -> None:
    for code, where in c.exceptions.items():
        if code in draft.replies or where.file.endswith("standard.gen"):
            continue
        throwers = [s for s in services.values() if code in s.listed("throws")]
        rejects = bool(throwers) and all(s.validate and not s.codels for s in throwers)
        mixed = [s.name for s in throwers if s.validate and s.codels]
        by = ", ".join(s.name for s in throwers)
        draft.replies[code] = ("R", f"{c.name}: only validate codels throw it ({by})") if rejects else \
            ("T", f"exception {code} of {c.name} ({where}): the service ended with it")
        if mixed and not rejects:
            draft.notes.append(f"{c.name}: {code} may come from the validate codel of {', '.join(mixed)} (a "
                               "rejection) or from their other codels (an end): catalogued T")


def _component(c: GenomScope, draft: Draft) -> None:
    services = {n: s for n, s in c.services.items() if n not in UNUSABLE or s.scope != "genom"}
    draft.modules[c.name] = {n: _kind(s) for n, s in services.items()}
    draft.left_out.add(f"{c.name}.kill")  # it ends the component: never in the golden mission
    _preconditions(c, services, draft)
    _dominators(c, services, draft)
    _exceptions(c, services, draft)
    validated(c, services, draft)
    draft.notes += c.notes
    draft.notes.append(f"{c.name}: genom3's standard services {', '.join(UNUSABLE)} are left out (they name an "
                       "activity or a port by an identifier of the middleware, which a mission cannot know)")


def from_genom(path: Path, includes: list[Path]) -> Draft:
    """The draft a GenoM3 description states; refused when a component states no property."""
    components, interfaces, source = read_scopes(path, includes)
    draft = Draft(f"the GenoM3 description {path.name}", {})
    draft.replies.update(STANDARD_REPLIES)
    for c in components:
        provided(c, interfaces, source.pragmas)
        before = len(draft.properties)
        _component(c, draft)
        if len(draft.properties) == before:
            raise InputFileError(c.where.file, c.where.line, f"component {c.name} states no property untimely can "
                                 "judge (no activity, so nothing to interrupt, no after or before clause, and no "
                                 "validate codel that rejects with an exception of its own); "
                                 "write the target by hand from `untimely init DIR` (without --from-genom)")
    draft.notes += [f"#pragma {words} ({where}) concerns genom3's build, not the interface: ignored"
                    for where, words in source.pragmas if words.split()[:1] != ["provides"]]
    draft.notes += ["service inputs other than those a rejecting validate codel checks (the args of interface.toml) "
                    "are not derived, nor any argument's bounds: add them to interface.toml and golden.mission",
                    "which activities run until stopped is not derived: the golden mission waits for each "
                    "activity at most 30 s",
                    "cross-component exclusions (EXC, MX_I) are stated nowhere in a .gen file: add them to "
                    "properties.toml by hand"]
    return draft
