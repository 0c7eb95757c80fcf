"""`untimely init DIR [--from-genom FILE.gen]`: a target folder to start from, that already runs.

It writes interface.toml, properties.toml and golden.mission (commented, from a small example robot
or from what a GenoM3 description states: harness.target.genom), suts.toml, and adapter.py: a
standard-library untimely/1 adapter that stands in for the layer until the user connects theirs.
The golden mission sets every module up, then requests every other service once, one at a time
(each service's `after` services first), then the modules' Stop services.
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass, field
from pathlib import Path

from harness.errors import UntimelyError
from harness.files import make_folder
from harness.target.genom import read_genom

SKELETON = Path(__file__).resolve().parent / "skeleton"
WRITTEN = ("interface.toml", "properties.toml", "golden.mission", "suts.toml", "adapter.py")
# The catalogue every draft starts from: (class, what it means).
REPLIES = {"ok": ("T", "the service ended normally"),
           "interrupted": ("Z", "interrupted by a dominating request of the same module"),
           "wait_init": ("R", "the module is not set up: its init service has not ended ok"),
           "disallowed": ("R", "a service that must come first has not ended ok"),
           "bad_params": ("R", "argument values outside their domain")}
WAIT_TIMEOUT_S = 30  # a golden wait gives up after this, should an activity never end by itself


@dataclass
class Draft:
    """A target's interface and properties, with the comments they are written with."""
    source: str
    modules: dict[str, dict[str, str]]  # module -> service -> kind, in declared order
    properties: list[dict] = field(default_factory=list)  # [[property]] entries, "why" a comment
    replies: dict[str, tuple[str, str]] = field(default_factory=lambda: dict(REPLIES))
    notes: list[str] = field(default_factory=list)  # what could not be derived


def example() -> Draft:
    """A two-module robot whose properties show the three families a GenoM layer states."""
    draft = Draft("an example robot: replace its modules and services by your layer's",
                  {"base": {"Init": "init", "SetSpeed": "control", "Move": "exec", "Stop": "exec"},
                   "camera": {"Init": "init", "Capture": "exec", "Stop": "exec"}})
    for module in draft.modules:
        draft.properties.append(_pex(draft, module, "Init"))
    draft.properties.append(_aib("base.Move", ["base.Move", "base.Stop"]))
    draft.properties.append(_aib("camera.Capture", ["camera.Capture", "camera.Stop"]))
    draft.properties.append(_pre("base.Move", ["base.SetSpeed"]))
    return draft


def _pex(draft: Draft, module: str, init: str) -> dict:
    execs = [f"{module}.{s}" for s, kind in draft.modules[module].items() if kind == "exec"]
    return {"id": f"PEX({module})", "family": "PEX", "type": "PC", "x": execs, "q": [f"{module}.{init}"],
            "r_p": "wait_init", "why": f"an exec request of {module} needs an earlier ok of {module}.{init}"}


def _aib(x: str, dominators: list[str]) -> dict:
    return {"id": f"AIB({x})", "family": "AIB", "type": "EE", "x": [x], "y": dominators, "z_p": "interrupted",
            "why": f"a running {x} is interrupted by {', '.join(dominators)}"}


def _pre(x: str, first: list[str]) -> dict:
    return {"id": f"PRE({x})", "family": "PRE", "type": "PC", "x": [x], "q": first, "r_p": "disallowed",
            "why": f"{x} needs an earlier ok of {', '.join(first)}"}


def from_genom(path: Path) -> Draft:
    """The draft a GenoM3 description states (module = component)."""
    components = read_genom(path)
    draft = Draft(f"the GenoM3 description {path.name}", {c.name: {s.name: s.kind for s in c.services.values()}
                                                          for c in components})
    for component in components:
        module, services = component.name, component.services
        for code in component.exceptions:
            draft.replies.setdefault(code, ("T", f"exception {code} of {module}: the activity ended with it"))
        inits = [s.name for s in services.values() if s.kind == "init"]
        if inits:
            draft.properties.append(_pex(draft, module, inits[0]))
        else:
            draft.notes.append(f"{module}: no init service (a service named init), so no PEX property")
        dominators: dict[str, list[str]] = {}
        for s in services.values():
            named = list(services) if s.interrupts == ["all"] else s.interrupts
            for target in named:
                if target not in services:
                    draft.notes.append(f"{module}.{s.name} (line {s.line}) interrupts {target!r}, which the "
                                       "component does not declare: left out")
                elif services[target].kind == "exec":
                    dominators.setdefault(target, []).append(f"{module}.{s.name}")
            first = [f"{module}.{q}" for q in s.after if q in services and q not in inits]  # inits: PEX
            draft.notes += [f"{module}.{s.name} (line {s.line}) comes after {q!r}, which the component does "
                            "not declare: left out" for q in s.after if q not in services]
            if first:
                draft.properties.append(_pre(f"{module}.{s.name}", first))
        draft.properties += [_aib(f"{module}.{x}", dominators[x]) for x in services if x in dominators]
    draft.notes += ["service inputs (the args of interface.toml) and their domains (validate codels) are not "
                    "derived: add args to interface.toml and values to golden.mission",
                    "which activities run until stopped (until_stopped) is not derived",
                    "cross-component exclusions (EXC, MX_I) are stated nowhere in a .gen file: add them to "
                    "properties.toml by hand"]
    return draft


def _toml_list(names: list[str]) -> str:
    return "[" + ", ".join(f'"{n}"' for n in names) + "]"


def interface_text(draft: Draft) -> str:
    lines = [f"# The interface of the layer under test, made by `untimely init` from {draft.source}.",
             "# Black-box knowledge only: modules, their services and kinds, and the reply catalogue",
             "# (docs/reference/interface.md). kind: init (sets the module up), control (replies at once),",
             "# exec (starts an activity). A service may take arguments:",
             '#   services.Goto = { kind = "exec", args = { x = { type = "float", min = -10.0, max = 10.0 } } }',
             "", "[replies]  # every final reply code, with its class: T ends, Z interrupted, R rejected"]
    lines += [f'{code} = "{cls}"  # {meaning}' for code, (cls, meaning) in draft.replies.items()]
    for module, services in draft.modules.items():
        lines += ["", f"[modules.{module}]"]
        lines += [f'services.{name} = {{ kind = "{kind}" }}' for name, kind in services.items()]
    return "\n".join(lines) + "\n"


def properties_text(draft: Draft) -> str:
    lines = ["# The safety properties the oracles judge (docs/reference/properties.md): one [[property]] each,",
             "# of a basic type PC, ES, EE, EX, MX_R or MX_I over services of interface.toml.",
             "# Edit, then `untimely analyze` judges every stored trace again (nothing is re-run)."]
    for p in draft.properties:
        lines += ["", f"# {p['why']}", "[[property]]"]
        lines += [f'{key} = {_toml_list(value) if isinstance(value, list) else chr(34) + value + chr(34)}'
                  for key, value in p.items() if key != "why"]
    return "\n".join(lines) + "\n"


def _ordered(draft: Draft, module: str) -> list[str]:
    """A module's non-init services, each after the services it comes after, Stop last."""
    requires = {p["x"][0]: p["q"] for p in draft.properties if p["family"] == "PRE"}
    done: list[str] = []

    def visit(service: str, seen: tuple = ()) -> None:
        if service in done or service in seen:
            return
        for first in requires.get(service, []):
            if first.startswith(module + "."):
                visit(first, seen + (service,))
        done.append(service)
    services = draft.modules[module]
    for name in sorted((s for s in services if services[s] != "init"), key=lambda s: s == "Stop"):
        visit(f"{module}.{name}")
    return done


def golden_text(draft: Draft) -> str:
    def handle(service: str) -> str:
        return service.replace(".", "_").lower()
    lines = ["# The golden mission (docs/reference/mission-language.md): a valid run the mutants start from.",
             "# Set every module up, then use each service once.", ""]
    inits = [f"{m}.{s}" for m, services in draft.modules.items() for s, kind in services.items() if kind == "init"]
    lines += [f"send {s} as {handle(s)}" for s in inits]
    lines += ["wait all"] if inits else []
    for module in draft.modules:
        for service in _ordered(draft, module):
            lines += [f"send {service} as {handle(service)}", f"wait {handle(service)} timeout={WAIT_TIMEOUT_S}"]
    return "\n".join(lines) + "\n"


def new_target_folder(folder: Path, names: tuple[str, ...]) -> None:
    """Create the folder `init` writes `names` into; refuses one that holds any of them."""
    existing = [name for name in names if (folder / name).exists()]
    if existing:
        raise UntimelyError(f"{folder} already holds {', '.join(existing)}; `untimely init` writes a new target "
                            "folder: give another DIR, or move those files away")
    make_folder(folder, "the target")


def write(folder: Path, draft: Draft) -> list[Path]:
    """Write the target folder; refuses to overwrite any file of it."""
    new_target_folder(folder, WRITTEN)
    texts = {"interface.toml": interface_text(draft), "properties.toml": properties_text(draft),
             "golden.mission": golden_text(draft)}
    for name, text in texts.items():
        (folder / name).write_text(text)
    for name in ("suts.toml", "adapter.py"):
        shutil.copyfile(SKELETON / name, folder / name)
    return [folder / name for name in WRITTEN]


def main(args) -> int:
    folder = Path(args.dir)
    if args.from_genom and not Path(args.from_genom).is_file():
        raise UntimelyError(f"--from-genom {args.from_genom!r}: no such file; give a GenoM3 .gen file")
    draft = from_genom(Path(args.from_genom)) if args.from_genom else example()
    write(folder, draft)
    print(f"wrote the target {folder}/ from {draft.source}: {', '.join(WRITTEN)}")
    print(f"  {sum(len(s) for s in draft.modules.values())} services in {len(draft.modules)} modules, "
          f"{len(draft.properties)} properties")
    for note in draft.notes:
        print(f"  not derived: {note}")
    print(f"next: untimely run {folder}/golden.mission --sut adapter\n"
          f"      untimely campaign --mission {folder} --sut adapter --mutants 20")
    return 0
