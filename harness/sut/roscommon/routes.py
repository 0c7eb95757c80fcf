"""How one service of the interface reaches ROS 1 or ROS 2 (a `[services."module.Service"]` table of
ros.toml or ros2.toml; a ROS 2 type may also be written "package/action/Name" or "package/srv/Name").

Three kinds, each a choice per service:

- the generic action `untimely_msgs/Request` (the default): the goal names the service and carries
  its arguments as JSON, so one action server may serve a whole module;
- a typed action (`action = NAME`, `type = "move_base_msgs/MoveBase"`): `fields` says which goal
  field each argument fills, `defaults` fills the fields the script does not set; the result's
  code field (`code`, if the result has one) or the status text gives the final reply;
- a ROS service (`service = NAME`, `type = "std_srvs/Trigger"`): the request's fields as above; the
  response is the final reply: its `code` field when the catalogue knows the text, else `ok` when
  its `success` field is true, else `failure`;
- ROS 2 only, the generic service `untimely_msgs/Call` (the mapping's `service` template, for
  `control` and `init` services): the request names the service and carries its arguments as JSON,
  the response's `code` is the final reply.

No ROS import: the file is checked anywhere.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field

from harness.errors import InputFileError

GENERIC_TYPE = "untimely_msgs/Request"
GENERIC_SERVICE_TYPE = "untimely_msgs/Call"  # ROS 2: a service call naming the service, JSON arguments
ROUTE_KEYS = {"action", "service", "type", "definition", "fields", "defaults", "code", "success", "failure"}


@dataclass(frozen=True)
class Route:
    kind: str  # "action" or "service"
    name: str  # the action server's or ROS service's name
    type: str  # "package/Name" (ROS 2 also "package/action/Name", "package/srv/Name"); GENERIC_TYPE for the generic action
    fields: dict[str, str] = field(default_factory=dict)  # argument -> goal or request field ("a.b.c")
    defaults: dict[str, object] = field(default_factory=dict)  # field -> value the script does not set
    code: str | None = None  # result or response field carrying the reply code
    success: str | None = None  # ROS service: bool response field, true -> ok
    failure: str = "failure"  # ROS service: the code of a response that is neither
    definition: str | None = None  # .action or .srv file (beside the mapping) for a type no package has

    @property
    def generic(self) -> bool:
        return self.type in (GENERIC_TYPE, GENERIC_SERVICE_TYPE)

    def response_code(self, response, catalogue: dict[str, str]) -> str:
        """The final reply of a ROS service's response."""
        text = read_field(response, self.code) if self.code else None
        if text in catalogue:
            return text
        if self.success and read_field(response, self.success):
            return "ok"
        return self.failure


def read_field(message, path: str):
    for name in path.split("."):
        message = getattr(message, name)
    return message


def generic_arguments(goal) -> dict | None:
    """The arguments a goal or call of the generic type carries (its `args_json`, a JSON object);
    None when that is not one."""
    try:
        args = json.loads(goal.args_json or "{}")
    except ValueError:
        return None
    return args if isinstance(args, dict) else None


def _text(path, key: str, value) -> str:
    if not isinstance(value, str) or not value:
        raise InputFileError(path, key, f"{key} = {value!r}; give a non-empty string")
    return value


def parse_route(path, service: str, value) -> Route:
    """A [services] entry: a string is the generic action's name; a table names a type."""
    key = f"[services] {service}"
    if isinstance(value, str):
        return Route("action", _text(path, key, value), GENERIC_TYPE)
    if not isinstance(value, dict):
        raise InputFileError(path, key, f"{value!r} is neither an action name nor a table")
    unknown = set(value) - ROUTE_KEYS
    if unknown:
        raise InputFileError(path, key, f"unknown key(s) {sorted(unknown)}; a route takes {', '.join(sorted(ROUTE_KEYS))}")
    kinds = [kind for kind in ("action", "service") if kind in value]
    if len(kinds) != 1:
        raise InputFileError(path, key, "give exactly one of action = NAME or service = NAME")
    kind = kinds[0]
    type_ = _text(path, f"{key}.type", value.get("type", GENERIC_TYPE if kind == "action" else ""))
    if type_.count("/") not in (1, 2):
        raise InputFileError(path, f"{key}.type", f"type = {type_!r} is not \"package/Name\" (ROS 2: "
                                                  "\"package/action/Name\" or \"package/srv/Name\")")
    if kind == "service" and type_ == GENERIC_TYPE:
        raise InputFileError(path, f"{key}.type", f"{GENERIC_TYPE} is an action; give the ROS service's type")
    fields = value.get("fields", {})
    defaults = value.get("defaults", {})
    for table, entries in (("fields", fields), ("defaults", defaults)):
        if not isinstance(entries, dict):
            raise InputFileError(path, f"{key}.{table}", f"{table} = {entries!r}; give a table")
    for argument, target in fields.items():
        _text(path, f"{key}.fields.{argument}", target)
    if type_ == GENERIC_TYPE and (fields or defaults):
        raise InputFileError(path, key, f"{GENERIC_TYPE} carries the arguments as JSON; fields and defaults need a type")
    options = {name: _text(path, f"{key}.{name}", value[name]) for name in ("code", "success", "failure", "definition") if name in value}
    if kind == "action" and ({"success", "failure"} & set(options)):
        raise InputFileError(path, key, "success and failure are for ROS services; an action ends with its goal status")
    return Route(kind, _text(path, f"{key}.{kind}", value[kind]), type_, dict(fields), dict(defaults), **options)
