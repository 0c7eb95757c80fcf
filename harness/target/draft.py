"""A target drafted by `untimely init`: its interface, properties, golden mission and the rules
of the stand-in layer, with the comments they are written with (harness.target.scaffold writes
them; harness.target.genom.derive drafts one from a GenoM3 description)."""
from __future__ import annotations

import json
import textwrap
from dataclasses import dataclass, field

# The catalogue every draft starts from: (class, what it means).
REPLIES = {"ok": ("T", "the service ended normally"),
           "interrupted": ("Z", "interrupted by a dominating request of the same module"),
           "wait_init": ("R", "the module is not set up: its init service has not ended ok"),
           "disallowed": ("R", "a service that must come first has not ended ok"),
           "bad_params": ("R", "argument values outside their domain")}
WAIT_TIMEOUT_S = 30  # a golden wait gives up after this, should an activity never end by itself


@dataclass(frozen=True)
class DraftArg:
    """An argument of interface.toml (its type, no bounds) and the word the golden mission sends."""
    type: str  # float | str
    word: str
    doc: str = ""


@dataclass
class Draft:
    """A target's interface and properties, with the comments they are written with."""
    source: str
    modules: dict[str, dict[str, str]]  # module -> service -> kind, in declared order
    properties: list[dict] = field(default_factory=list)  # [[property]] entries; "why", "cites": comments
    replies: dict[str, tuple[str, str]] = field(default_factory=lambda: dict(REPLIES))
    notes: list[str] = field(default_factory=list)  # what could not be derived
    left_out: set[str] = field(default_factory=set)  # services the golden mission does not request
    args: dict[str, dict[str, DraftArg]] = field(default_factory=dict)  # "module.Service" -> name -> argument


def pex(draft: Draft, module: str, init: str, r_p: str = "wait_init", cites: tuple = ()) -> dict:
    execs = [f"{module}.{s}" for s, kind in draft.modules[module].items() if kind == "exec"]
    return {"id": f"PEX({module})", "family": "PEX", "type": "PC", "x": execs, "q": [f"{module}.{init}"],
            "r_p": r_p, "why": f"an exec request of {module} needs an earlier ok of {module}.{init}", "cites": cites}


def aib(x: str, dominators: list[str], cites: tuple = ()) -> dict:
    return {"id": f"AIB({x})", "family": "AIB", "type": "EE", "x": [x], "y": dominators, "z_p": "interrupted",
            "why": f"a running {x} is interrupted by {', '.join(dominators)}", "cites": cites}


def pre(x: str, first: list[str], cites: tuple = ()) -> dict:
    return {"id": f"PRE({x})", "family": "PRE", "type": "PC", "x": [x], "q": first, "r_p": "disallowed",
            "why": f"{x} needs an earlier ok of {', '.join(first)}", "cites": cites}


def val(x: str, reply: str, args: list[str], cites: tuple = ()) -> dict:
    return {"id": f"VAL({x})", "family": "VAL", "type": "VAL", "x": [x], "r_p": reply,
            "why": f"{x} accepts only values of {', '.join(args)} within their domains of interface.toml, "
                   f"and rejects the others with {reply}", "cites": cites}


def _toml_list(names: list[str]) -> str:
    return "[" + ", ".join(f'"{n}"' for n in names) + "]"


def _entry(p: dict, keys: tuple[str, ...]) -> list[str]:
    return [f'{key} = {_toml_list(p[key]) if isinstance(p[key], list) else chr(34) + p[key] + chr(34)}'
            for key in keys if key in p]


def _args(args: dict[str, DraftArg]) -> str:
    """The `args` table of a service in interface.toml (a TOML inline table: JSON's strings are TOML's)."""
    if not args:
        return ""
    specs = [f'{name} = {{ type = "{a.type}"' + (f", doc = {json.dumps(a.doc)}" if a.doc else "") + " }"
             for name, a in args.items()]
    return f", args = {{ {', '.join(specs)} }}"


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
        lines += [f'services.{name} = {{ kind = "{kind}"{_args(draft.args.get(f"{module}.{name}", {}))} }}'
                  for name, kind in services.items()]
    return "\n".join(lines) + "\n"


BASIC_TYPES = "a basic type PC, ES, EE, EX, MX_R, MX_I or VAL"


def properties_text(draft: Draft, types: str = BASIC_TYPES) -> str:
    """properties.toml: each property after its comment (its "why", wrapped, and its cites)."""
    lines = ["# The safety properties the oracles judge (docs/reference/properties.md): one [[property]] each,",
             f"# of {types} over services of interface.toml.",
             "# Edit, then `untimely analyze` judges every stored trace again (nothing is re-run)."]
    for p in draft.properties:
        lines += ["", *(f"# {line}" for line in textwrap.wrap(p["why"], 98))]
        lines += [f"#   from {cite}" for cite in p.get("cites", ())] + ["[[property]]"]
        lines += _entry(p, ("id", "family", "type", "x", "q", "y", "r_p", "z_p"))
    return "\n".join(lines) + "\n"


def standin_text(draft: Draft) -> str:
    """The rules the stand-in layer (adapter.py) follows: those the drafted properties state, so
    that a campaign on it finds no fault until the real layer is connected."""
    lines = ["# What the stand-in layer of adapter.py does, written by `untimely init` with the properties:",
             "# [[requires]]: a request of x is rejected with `reply` until every q has ended ok once;",
             "# [[interrupts]]: an accepted request of `by` interrupts the running x activities with `reply`;",
             "# [[validates]]: a request of x whose arguments break their domain in interface.toml is rejected",
             "# with `reply` (after the [[requires]] rules, as genom3 runs a validate codel after them).",
             "# Replace adapter.py by your layer's adapter; this file is then no longer read."]
    for p in draft.properties:
        if p["type"] == "PC":
            lines += ["", f"# {p['id']}", "[[requires]]", *_entry(p, ("x", "q")), f'reply = "{p["r_p"]}"']
    dominated: dict[str, list[str]] = {}
    for p in draft.properties:
        for y in p["y"] if p["type"] == "EE" else []:
            dominated.setdefault(y, []).extend(x for x in p["x"] if x not in dominated.get(y, []))
    for by, x in dominated.items():
        lines += ["", "[[interrupts]]", f'by = "{by}"', f"x = {_toml_list(x)}", 'reply = "interrupted"']
    for p in draft.properties:
        if p["type"] == "VAL":
            lines += ["", f"# {p['id']}", "[[validates]]", *_entry(p, ("x",)), f'reply = "{p["r_p"]}"']
    return "\n".join(lines) + "\n"


def _ordered(draft: Draft, module: str) -> list[str]:
    """A module's services, each after those it needs an ok of (its PC properties' q)."""
    requires: dict[str, list[str]] = {}
    for p in draft.properties:
        for x in p["x"] if p["type"] == "PC" else []:
            requires.setdefault(x, []).extend(p["q"])
    done: list[str] = []

    def visit(service: str, seen: tuple = ()) -> None:
        if service in done or service in seen:
            return
        for first in requires.get(service, []):
            visit(first, seen + (service,))
        done.append(service)
    services = draft.modules[module]
    for name in sorted(services, key=lambda s: services[s] != "init"):
        if f"{module}.{name}" not in draft.left_out:
            visit(f"{module}.{name}")
    return [s for s in done if s.startswith(module + ".")]


def golden_text(draft: Draft) -> str:
    """Every service once, each after those it needs: an activity, and a service another one needs,
    is awaited with `wait all` before the next request; other control requests go out between
    them. No request has a handle, so that deleting or swapping a request (the mutation
    operators) leaves a valid script."""
    needed = {q for p in draft.properties if p["type"] == "PC" for q in p["q"]}
    lines = ["# The golden mission (docs/reference/mission-language.md): a valid run the mutants start from.",
             "# Each service once, after the services it needs; `wait all` after each activity and after",
             "# each service another one needs (its ok must have come back before that one is sent)."]
    for module, services in draft.modules.items():
        lines += ["", f"# {module}"]
        for service in _ordered(draft, module):
            args = draft.args.get(service, {})
            lines.append(" ".join([f"send {service}", *(f"{name}={a.word}" for name, a in args.items())]))
            if services[service.split(".", 1)[1]] != "control" or service in needed:
                lines.append(f"wait all timeout={WAIT_TIMEOUT_S}")
    lines.append(f"wait all timeout={WAIT_TIMEOUT_S}")
    return "\n".join(lines) + "\n"
