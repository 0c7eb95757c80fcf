"""What the bag readers share: the interface's routes (ros.toml), a goal's arguments and its final code."""
from __future__ import annotations

from harness.sut.roscommon.mapping import Mapping
from harness.sut.roscommon.routes import Route, generic_arguments, read_field
from harness.errors import UntimelyError
from harness.target.interface import Interface


class Routes:
    def __init__(self, interface: Interface, mapping: Mapping):
        self.interface, self.mapping = interface, mapping
        unknown = sorted(set(mapping.overrides) - set(interface.services))
        if unknown:  # a misspelt service would silently not be imported
            raise UntimelyError(f"{mapping.path}: [services] names {unknown[0]!r}, which the interface "
                                f"{interface.path} does not declare; its services are "
                                f"{', '.join(sorted(interface.services))}: fix or remove the entry")
        self.by_service = mapping.routes([(s.module, s.name) for s in interface.services.values()],
                                         {qualified: s.kind for qualified, s in interface.services.items()})
        self.catalogue = dict(interface.replies)

    def named(self, kind: str) -> dict[str, list[tuple[str, Route]]]:
        """Each action's or ROS service's name -> the services it carries."""
        found: dict[str, list[tuple[str, Route]]] = {}
        for qualified, route in self.by_service.items():
            if route.kind == kind:
                found.setdefault(route.name, []).append((qualified, route))
        return found

    def target(self, carried: list[tuple[str, Route]], goal) -> tuple[str, dict | None] | None:
        """(service, arguments) of a goal or request of the route(s) `carried`; None when a generic
        goal names a service the route does not carry."""
        qualified, route = carried[0]
        if route.generic:
            service = next((q for q, _ in carried if q.split(".")[1] == goal.service), None)
            if service is None:
                return None
            return service, generic_arguments(goal)
        if len(carried) > 1:  # services sharing one ROS service (lifecycle transitions) differ by their defaults
            qualified, route = _by_defaults(carried, goal, self.mapping.path)
        args = {argument: _field(goal, path, qualified, self.mapping.path) for argument, path in route.fields.items()}
        known = self.interface.services[qualified].args
        return qualified, {k: float(v) if k in known and known[k].type == "float" else v for k, v in args.items()}

    def final_code(self, route: Route, status: str, result, status_text: str) -> str | None:
        """As the live adapter (Mapping.final_code): the result's code field, the status text, the fallback."""
        code = getattr(result, route.code or "code", None) if result is not None else None
        return self.mapping.final_code(status, (code, status_text), self.catalogue)


def check_type(connection, expected: str, what: str) -> None:
    """A mapped topic must carry what its name says, `expected` (a type name's end, or a full type
    name): a foreign type would be read as something it is not."""
    if not (connection.msgtype == expected if "/" in expected else connection.msgtype.endswith(expected)):
        raise UntimelyError(f"topic {connection.topic} carries {connection.msgtype}, not {what} "
                            f"({'...' if '/' not in expected else ''}{expected}); record the server's own topics, "
                            "or map the service to the action or service that has them")


def _field(goal, path: str, qualified: str, mapping: str):
    """The goal's field `path` that the route of `qualified` reads for an argument."""
    try:
        return read_field(goal, path)
    except AttributeError:
        fields = ", ".join(f for f in getattr(type(goal), "__dataclass_fields__", {}) if not f.startswith("_"))
        kind = getattr(goal, "__msgtype__", type(goal).__name__)
        raise UntimelyError(f"{mapping}: [services] {qualified} reads the field {path!r} of its goal, which the "
                            f"bag's {kind} lacks (its fields: {fields or 'none'}); name a field it has") from None


def _by_defaults(carried: list[tuple[str, Route]], request, mapping: str) -> tuple[str, Route]:
    """The one of several services mapped to one ROS service whose `defaults` the request carries."""
    for qualified, route in carried:
        if route.defaults and all(_field(request, path, qualified, mapping) == value
                                  for path, value in route.defaults.items()):
            return qualified, route
    if not any(route.defaults for _, route in carried):
        return carried[0]
    raise UntimelyError(f"{mapping}: a request of {carried[0][1].name} carries the defaults of none of "
                        f"{', '.join(q for q, _ in carried)} ({request!r:.200}); give each of them defaults "
                        "that tell its requests apart")
