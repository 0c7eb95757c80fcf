"""The basic property types, read from the oracle templates (docs/reference/verdicts.md): a template
sql/oracles/<type>.sql (not starting with `_`) defines a type named <TYPE>, and its macro
`ctes(name, ...)` declares the parameters a property of that type gives, in order; a type whose
activities a request may interrupt says so with `{% set interrupts = [['x', 'y']] %}`. A new type
is a new template (and the fixtures that test it); no Python changes.
"""
from __future__ import annotations

from functools import cache
from pathlib import Path

import jinja2
from jinja2 import nodes

from harness import SQL_DIR
from harness.errors import PropertyError

TEMPLATES = SQL_DIR / "oracles"
# What a properties file can say of a property: request types (lists of "module.Service") and
# reply codes of class R (r_p) or Z (z_p). A template may take any of them.
SERVICE_LISTS = ("x", "y", "q")
REPLY_CODES = {"r_p": "R", "z_p": "Z"}
# ... and a state-dependent domain: argument -> the bounds that hold while a y runs (docs/targets.md);
# and a deadline in seconds (the ROS 2 types, sql/oracles/_deadline.sql: derived from the golden runs
# when a property leaves it out).
DOMAIN = "domain"
DEADLINE = "deadline"
PARAMETERS = (*SERVICE_LISTS, *REPLY_CODES, DOMAIN, DEADLINE)


def _tree(path: Path) -> nodes.Template:
    try:
        return jinja2.Environment().parse(path.read_text())
    except (OSError, jinja2.TemplateSyntaxError) as e:
        raise PropertyError(f"the oracle template {path} cannot be read: {e}; fix it or remove it") from None


def _parameters(path: Path) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The parameters the template's ctes macro declares, and those of them it gives a default."""
    tree = _tree(path)
    macro = next((m for m in tree.find_all(nodes.Macro) if m.name == "ctes"), None)
    if macro is None or not macro.args or macro.args[0].name != "name":
        raise PropertyError(f"the oracle template {path} defines no macro ctes(name, ...); a type's template "
                            "defines its CTE chain as {% macro ctes(name, x, ...) %} (see sql/oracles/pc.sql)")
    declared = tuple(a.name for a in macro.args[1:])
    unknown = [p for p in declared if p not in PARAMETERS]
    if unknown or "x" not in declared:
        raise PropertyError(f"the oracle template {path} declares ctes{('name', *declared)}: "
                            f"{'parameter ' + repr(unknown[0]) if unknown else 'no x'}; a type takes x and any "
                            f"of {', '.join(p for p in PARAMETERS if p != 'x')}")
    return declared, tuple(a.name for a in macro.args[len(macro.args) - len(macro.defaults):])


def property_types(folder: Path | None = None) -> dict[str, tuple[str, ...]]:
    """Type name (PC, ES, ...) -> the parameters its properties give, x first."""
    return {name: ("x",) + tuple(p for p in declared if p != "x") for name, (declared, _) in _templates(folder).items()}


def optional_parameters(folder: Path | None = None) -> dict[str, tuple[str, ...]]:
    """Type name -> the parameters its properties may leave out (a default in its ctes macro)."""
    return {name: optional for name, (_, optional) in _templates(folder).items()}


def _templates(folder: Path | None) -> dict[str, tuple[tuple[str, ...], tuple[str, ...]]]:
    return {path.stem.upper(): _parameters(path) for path in _paths(folder)}


def _paths(folder: Path | None) -> list[Path]:
    return [path for path in sorted((folder or TEMPLATES).glob("*.sql")) if not path.name.startswith("_")]


def interruptions(folder: Path | None = None) -> dict[str, tuple[tuple[str, str], ...]]:
    """Type name -> the (ended, ender) role pairs its template declares in `{% set interrupts = ... %}`:
    a request of the ender role (y) may end an activity of the ended role (x) with the property's
    z_p (EE: x by y; MX_I: both ways). A type that declares none has (): nothing interrupts."""
    folder = folder or TEMPLATES
    return _interruptions(folder, folder.stat().st_mtime_ns)


# Oracles and the mutator ask once per property: read once per folder and time of change (a template
# added or removed); a template edited in place is read again by the next command.
@cache
def _interruptions(folder: Path, _changed: int) -> dict[str, tuple[tuple[str, str], ...]]:
    return {path.stem.upper(): _interrupts(path) for path in _paths(folder)}


def _interrupts(path: Path) -> tuple[tuple[str, str], ...]:
    assigned = [a.node for a in _tree(path).body if isinstance(a, nodes.Assign)
                and isinstance(a.target, nodes.Name) and a.target.name == "interrupts"]
    try:
        pairs = tuple(tuple(pair) for pair in assigned[0].as_const()) if assigned else ()
    except (nodes.Impossible, TypeError):
        pairs = None
    declared = _parameters(path)[0]
    if pairs is None or any(len(p) != 2 or not set(p) <= set(SERVICE_LISTS) & set(declared) for p in pairs) \
            or (pairs and "z_p" not in declared):
        raise PropertyError(f"the oracle template {path} sets interrupts to something other than a list of "
                            "[ended, ender] role pairs among the service lists its ctes macro takes, with z_p; "
                            "write e.g. {% set interrupts = [['x', 'y']] %} (see sql/oracles/ee.sql)")
    return pairs
