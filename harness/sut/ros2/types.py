"""The rclpy classes of a route's type: a package importable in the distro's venv, or the project's
generic untimely_msgs types (built by `make ros2`). Runs only under a distro's interpreter."""
from __future__ import annotations

import importlib
import json

from harness.sut.roscommon.routes import Route
from harness.errors import UntimelyError


def interface_class(full_type: str, kind: str):
    """The class of "package/Name" (looked up in package.`kind`) or "package/kind/Name"."""
    parts = full_type.split("/")
    package, name = (parts[0], parts[-1])
    if len(parts) == 3 and parts[1] != kind:
        raise UntimelyError(f"{full_type} is a {parts[1]}; this route needs a {kind} type "
                            f"(\"{package}/{kind}/{name}\")")
    try:
        return getattr(importlib.import_module(f"{package}.{kind}"), name)
    except (ImportError, AttributeError) as e:
        raise UntimelyError(f"{package}.{kind}.{name} cannot be imported in this ROS 2 venv ({e}); install the "
                            f"package's wheel (ros-<distro>-{package.replace('_', '-')}) or build it beside "
                            "untimely_msgs (docs/ros2.md)") from None


def interface_name(route: Route) -> str:
    """The route's type as "package/action/Name" or "package/srv/Name"."""
    parts = route.type.split("/")
    return route.type if len(parts) == 3 else f"{parts[0]}/{'action' if route.kind == 'action' else 'srv'}/{parts[1]}"


def route_class(route: Route):
    """The action class of an action route, the service class of a service route."""
    return interface_class(route.type, "action" if route.kind == "action" else "srv")


def fill(message, route: Route, args: dict):
    """A goal or request: JSON arguments for the generic types, else the route's defaults, then each
    argument in its field (ROS 2 messages take plain values; rclpy checks each field's type)."""
    if route.generic:
        message.args_json = json.dumps(args)
        return message
    for path, value in [*route.defaults.items(), *((route.fields.get(a), v) for a, v in args.items())]:
        if path is None:
            raise UntimelyError(f"an argument has no field in {route.type}: {sorted(set(args) - set(route.fields))}; "
                                "add it to the route's fields in the mapping file")
        *parents, last = path.split(".")
        target = message
        for name in parents:
            target = getattr(target, name)
        if last not in target.get_fields_and_field_types():
            raise UntimelyError(f"{route.type} has no field {path}; check the route's fields and defaults")
        kind = target.get_fields_and_field_types()[last]
        try:
            setattr(target, last, float(value) if kind in ("double", "float") else
                    int(float(value)) if "int" in kind else str(value) if kind == "string" else value)
        except (TypeError, ValueError, AssertionError) as e:
            raise UntimelyError(f"{value!r} cannot fill {route.type} field {path}, a {kind}: {e}") from None
    return message
