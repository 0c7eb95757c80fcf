"""What the bag readers share: the interface's routes (ros.toml), a goal's arguments and its final code."""
from __future__ import annotations

import json

from harness.adapters.ros.mapping import Mapping
from harness.adapters.ros.routes import Route, read_field
from harness.target.interface import Interface


class Routes:
    def __init__(self, interface: Interface, mapping: Mapping):
        self.interface, self.mapping = interface, mapping
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
            try:
                args = json.loads(goal.args_json or "{}")
            except ValueError:
                args = None
            return service, args if isinstance(args, dict) else None
        args = {argument: read_field(goal, path) for argument, path in route.fields.items()}
        known = self.interface.services[qualified].args
        return qualified, {k: float(v) if k in known and known[k].type == "float" else v for k, v in args.items()}

    def final_code(self, route: Route, status: str, result, status_text: str) -> str | None:
        """As the live adapter (Mapping.final_code): the result's code field, the status text, the fallback."""
        code = getattr(result, route.code or "code", None) if result is not None else None
        return self.mapping.final_code(status, (code, status_text), self.catalogue)
