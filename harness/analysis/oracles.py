"""Properties rendered into SQL through the Jinja templates of sql/ (docs/reference/verdicts.md).

A property is judged by its type's template, sql/oracles/<type>.sql, which defines the CTE
chain of that type; sql/oracles/_oracle.sql wraps it into one query returning verdict rows.
The templates say which parameters each type takes: a missing one (StrictUndefined) or one
the type does not take (an unknown macro argument) is refused here, naming the property.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import jinja2

from harness import DEFAULT_EPSILON_S
from harness.errors import PropertyError
from harness.store.sql import ENV, VERDICTS
from harness.target.interface import Interface, Property
from harness.target.property_types import PARAMETERS, interruptions, property_types

_TABLE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_SERVICE = re.compile(r"[^.\s']+\.[^.\s']+")


@dataclass(frozen=True)
class Shared:
    """The temporary tables that every oracle of an analysis reads, made once per events table
    (render_shared): its requests, the candidate causes of their ends, and each trace's epsilon."""
    requests: str
    causes: str
    epsilons: str


def _parameters(prop: Property) -> dict:
    """The parameters the property sets; an unset one stays undefined, so a template needing it fails."""
    given = {}
    for name in PARAMETERS:
        value = getattr(prop, name)
        if isinstance(value, (tuple, list)):
            bad = [s for s in value if not isinstance(s, str) or not _SERVICE.fullmatch(s)]
            if bad:
                raise PropertyError(f"property {prop.id!r}: {name} names {bad[0]!r}; "
                                    "write request types as \"module.Service\"")
            value = list(value)
        elif isinstance(value, dict):  # a state-dependent domain: argument -> its bounds
            value = {name: domain.spec() for name, domain in value.items()}
        if value:
            given[name] = value
    return given


def _services(parameters: dict) -> list[str]:
    """Every "module.Service" a property's parameters name (x, y, q), sorted."""
    return sorted({s for v in parameters.values() if isinstance(v, list) for s in v})


def verdict_values(properties: list[Property]) -> dict[str, set[str]]:
    """Every value the verdicts' text columns may hold (`named` of sql/views/verdicts.sql): the
    properties' ids and families, the modules and services they name (a verdict judges one of their
    requests), the verdicts."""
    services = [s.split(".") for p in properties for s in _services(_parameters(p))]
    return {"property_id": {p.id for p in properties}, "family": {p.family for p in properties},
            "module": {m for m, _ in services}, "service": {s for _, s in services}, "verdict": set(VERDICTS)}


def _scope(prop: Property, enders: list[tuple[str, str, str]]) -> tuple[list[str], list[str] | None]:
    """What the property's oracle reads (sql/oracles/_base.sql's `scope`): the requests of the
    modules of its services and of those that may interrupt them (`enders`), or, for a type whose
    template declares `{% set scope = 'services' %}`, of its own services alone (then given too)."""
    services = _services(_parameters(prop))
    modules = sorted({s.split(".")[0] for s in services} | {y.split(".")[0] for *_, y in enders})
    own = _declares(prop, "scope", "modules") == "services"
    return modules, services if own else None


def _declares(prop: Property, name: str, default):
    """What the template of the property's type sets `name` to (`{% set name = ... %}`)."""
    return getattr(ENV.get_template(_template(prop)).module, name, default)


def interrupters(properties: list[Property]) -> list[tuple[str, str, str]]:
    """(x service, interruption code, y service) for every request that a property says may end an
    x activity with that code: the ways its template declares (`interrupts`: EE's y ends x, MX_I's
    both ways). The cause of an interruption is looked for among them (sql/oracles/ee.sql)."""
    found, declared = set(), interruptions()
    for p in properties:
        ways = [(getattr(p, ended), getattr(p, ender)) for ended, ender in declared[p.type]] if p.z_p else []
        found |= {(x, p.z_p, y) for xs, ys in ways for x in xs for y in ys}
    return sorted(found)


def _template(prop: Property) -> str:
    return f"oracles/{str(prop.type).lower()}.sql"


def _table_name(name: str, role: str) -> None:
    if not _TABLE_NAME.fullmatch(name):
        raise PropertyError(f"{role} {name!r} is not a table name; use events or internal_events")


@dataclass(frozen=True)
class Judging:
    """What a property is judged over and beside. The interface, when given, says which requests
    may end an activity, and `peers` (the properties judged with it) on which other modules an
    interruption may come from (see sql/oracles/ee.sql). `runs`: whether the store has trace_runs,
    whose pings give a real-time trace its epsilon; `taken`: whether it has taken_events, where an
    SUT's `taken` replies place its requests. `shared`: the tables of render_shared, which the
    query reads instead of aggregating the requests and searching causes."""
    events: str = "events"
    epsilon: float = DEFAULT_EPSILON_S
    interface: Interface | None = None
    peers: tuple[Property, ...] | list[Property] = ()
    runs: bool = True
    taken: bool = True
    shared: Shared | None = None


def _checked(judging: Judging, into: str | None) -> None:
    """Refuses a table name or an epsilon that a query cannot be rendered with."""
    _table_name(judging.events, "events source")
    if into is not None:
        _table_name(into, "verdicts table")
    if judging.shared is not None:
        _table_name(judging.shared.requests, "requests table")
        _table_name(judging.shared.causes, "causes table")
        _table_name(judging.shared.epsilons, "epsilons table")
    epsilon = judging.epsilon
    if not (isinstance(epsilon, (int, float)) and math.isfinite(epsilon) and epsilon >= 0):
        raise PropertyError(f"epsilon = {epsilon!r}; give a margin in seconds, >= 0")


def _render(props: list[Property], judging: Judging, into: str | None, **context) -> str:
    """sql/oracles/_oracle.sql over the requests the properties `props` (all of one type) read."""
    _checked(judging, into)
    interface, shared = judging.interface, judging.shared
    enders = [e for e in interrupters([*props, *judging.peers]) if any(e[0] in p.x or e[0] in p.y for p in props)]
    scopes = [_scope(p, [e for e in enders if e[0] in p.x or e[0] in p.y]) for p in props]
    modules = sorted({m for ms, _ in scopes for m in ms})
    services = None if any(ss is None for _, ss in scopes) else sorted({s for _, ss in scopes for s in ss})
    if shared is not None:  # the shared search found the causes: the oracle reads only its own services
        services = sorted({s for p in props for s in _services(_parameters(p))})
    return ENV.get_template("oracles/_oracle.sql").render(
        template=_template(props[0]), into=into, shared=shared and shared.requests,
        shared_causes=shared and shared.causes, shared_epsilons=shared and shared.epsilons,
        services=services, events=judging.events, epsilon=round(float(judging.epsilon), 6), enders=enders,
        runs=judging.runs, taken=judging.taken, modules=modules,
        until_stopped=interface.until_stopped if interface else [],
        control=interface.of_kind("control") if interface else [],
        **({"domains": {name: {a.name: a.spec() for a in s.args.values()}
                        for name, s in interface.services.items()}} if interface else {}), **context)


def render_property(prop: Property, judging: Judging = Judging(), explain: list[tuple[int, int]] = (),
                    into: str | None = None) -> str:
    """The oracle query of one property over the events table `judging.events`: the verdicts
    columns. `explain`: (trace_id, rqst_id) pairs; then the query of the pairs that decided their
    conditions. `into`: a verdicts table; then the statement inserting the rows into it."""
    template = _template(prop)
    try:
        return _render([prop], judging, into, id=prop.id, family=prop.family, parameters=_parameters(prop),
                       explain=dict(traces=sorted({int(t) for t, _ in explain}),
                                    requests=[f"({int(t)}, {int(r)})" for t, r in explain]) if explain else None)
    except jinja2.TemplateNotFound as e:
        if e.name != template:
            raise
        raise PropertyError(f"property {prop.id!r}: type {prop.type!r} has no oracle template "
                            f"{template}; use one of {', '.join(property_types())}") from None
    except jinja2.UndefinedError as e:
        if "'domains'" in str(e):
            raise PropertyError(f"property {prop.id!r} of type {prop.type} reads the argument domains of "
                                "the interface; pass the interface (analyze --interface FILE)") from None
        raise PropertyError(f"property {prop.id!r} of type {prop.type}: {e}; "
                            "add it to the property's entry") from None
    except TypeError as e:
        raise PropertyError(f"property {prop.id!r} of type {prop.type}: {e} "
                            "(the type does not use it); remove it from the property's entry") from None


def one_pass(prop: Property) -> bool:
    """Whether the template of the property's type judges all its properties in one query (it
    defines the macro `one_pass`, sql/oracles/_parameters.sql); a type without it is judged
    property by property."""
    return _declares(prop, "one_pass", None) is not None


def render_one_pass(props: list[Property], judging: Judging, into: str) -> tuple[str, list[str]]:
    """The statement inserting the verdicts of every property of `props`, all of one type whose
    template has a one-pass form, into `into` (one query over their parameter table); and each
    property's own statement (render_property), which refuses any it cannot judge and is what an
    analysis falls back to when the one query fails."""
    alone = [render_property(p, judging, into=into) for p in props]
    judged = [{"id": p.id, "family": p.family, **_parameters(p)} for p in props]
    return _render(props, judging, into, judged=judged), alone


def oracle_statements(properties: list[Property], epsilon: float, interface: Interface | None, events: str,
                      into: str, shared: Shared | None = None) -> list[str]:
    """Each property's statement inserting its verdicts on `events` into the table `into`, judged
    beside the others (its peers say where an interruption may come from); the analysis and the
    in-memory judge (harness/analysis/judge.py) both fill their verdicts tables with these."""
    return [render_property(p, Judging(events, epsilon, interface, properties, shared=shared), into=into)
            for p in properties]


def render_shared(properties: list[Property], events: str, epsilon: float, interface: Interface | None,
                  into: Shared) -> str:
    """The statements making what every oracle of an analysis shares, once per events table
    (sql/oracles/_requests.sql): the tables `into` of `events`'s requests, of the candidate
    causes of their ends and of each trace's epsilon; the oracles read them when rendered with `shared=into`."""
    _table_name(events, "events source")
    _table_name(into.requests, "requests table")
    _table_name(into.causes, "causes table")
    _table_name(into.epsilons, "epsilons table")
    enders = interrupters(properties)
    scopes = [_scope(p, [e for e in enders if e[0] in p.x or e[0] in p.y]) for p in properties]
    # the requests every oracle reads, and no more: whole modules for those that search causes
    modules = sorted({m for ms, services in scopes if services is None for m in ms})
    services = sorted({s for _, ss in scopes for s in ss or () if s.split(".")[0] not in modules})
    return ENV.get_template("oracles/_requests.sql").render(
        events=events, into=into.requests, shared_causes=into.causes, shared_epsilons=into.epsilons, taken=True, runs=True,
        epsilon=round(float(epsilon), 6), enders=enders, modules=modules, services=services,
        args=any(_declares(p, "needs_args", False) for p in properties),
        until_stopped=interface.until_stopped if interface else [],
        control=interface.of_kind("control") if interface else [])


def render_unknown(prop: Property, events: str, into: str) -> str:
    """The statement giving verdict 'unknown' to every request the property judges, for when its
    oracle failed: the requests of its x services, and of the other roles its template declares
    (`{% set judges = [...] %}`, as the mutual types do)."""
    _table_name(events, "events source")
    _table_name(into, "verdicts table")
    roles = _declares(prop, "judges", ["x"])
    judged = sorted({s for role in roles for s in getattr(prop, role) or ()})
    return ENV.get_template("oracles/_unknown.sql").render(into=into, id=prop.id, family=prop.family,
                                                          events=events, judged=judged)
