"""The mapping file beside an interface (e.g. missions/dala/ros.toml): services -> actionlib actions or
ROS services (routes.py), goal statuses -> reply codes. Read by the adapter, the nodes and the bag
importer; no ROS import, so it can be checked anywhere."""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from harness.adapters.ros.routes import GENERIC_TYPE, Route, parse_route
from harness.errors import InputFileError, UntimelyError
from harness.target.interface import read_toml

# Terminal goal statuses that carry a reply (actionlib_msgs/GoalStatus names). LOST is not one:
# the client declared it, the server never ended the goal, so the adapter must not invent a final.
TERMINAL_STATUSES = ("SUCCEEDED", "ABORTED", "PREEMPTED", "REJECTED", "RECALLED")
DEFAULT_STATUS_CODES = {"SUCCEEDED": "ok", "ABORTED": "aborted", "PREEMPTED": "interrupted",
                        "REJECTED": "rejected", "RECALLED": "rejected"}
DEFAULT_ACTION = "/{module}"


@dataclass(frozen=True)
class Mapping:
    path: str
    action: str  # template of the generic action's name, from {module} and {service}
    overrides: dict[str, Route]  # "module.Service" -> its route, when not the template's generic action
    status_codes: dict[str, str]  # terminal status -> code when the result names none the catalogue knows
    heartbeat_stale_s: float  # a server whose last status is older than this (wall seconds) is not alive
    # Topics of std_msgs/String JSON, if the SUT has them; `stamp` is the instant's wall-clock epoch (time.time()).
    world_topic: str | None  # {stamp, kind, detail}: virtual damage
    internal_topic: str | None  # {goal_id, kind, code, stamp}: ground truth of each goal
    # {id}: the adapter publishes each ping on ping_topic; the SUT echoes it on pong_topic when alive
    ping_topic: str | None
    pong_topic: str | None

    @property
    def folder(self) -> Path:
        """Where the routes' definition files are."""
        return Path(self.path).parent

    def routes(self, services: list[tuple[str, str]]) -> dict[str, Route]:
        """The route of each (module, service), by "module.Service". A generic goal names its service,
        not its module, so two services of one name may not share a generic action; a typed action
        or a ROS service names neither, so it serves one service only."""
        routes: dict[str, Route] = {}
        for module, service in services:
            qualified = f"{module}.{service}"
            if qualified in self.overrides:
                route = self.overrides[qualified]
            elif "{module}" in self.action:
                route = Route("action", self.action.format(module=module, service=service), GENERIC_TYPE)
            else:
                raise UntimelyError(f"{self.path}: no action for {qualified}; add it under [services], "
                                    "or make `action` a template with {module}")
            clash = next((other for other, known in routes.items() if known.name == route.name and not (
                route.generic and known.generic and other.split(".")[1] != service)), None)
            if clash:
                raise UntimelyError(f"{self.path}: {clash} and {qualified} both map to {route.name}, where a goal "
                                    "or call could not tell them apart; give one of them another name")
            routes[qualified] = route
        return routes

    def final_code(self, status: str, texts: tuple[str | None, ...], catalogue: dict[str, str]) -> str | None:
        """The final reply of a goal that ended in `status` (a GoalStatus name) with the result's and the
        status's `texts`; None when the status is no ending the server declared (LOST), as no reply may
        be invented."""
        if status not in self.status_codes:
            return None
        if status != "SUCCEEDED":
            for text in texts:
                if text in catalogue:
                    return text
        return self.status_codes[status]



def interface_services(interface: dict) -> list[tuple[str, str]]:
    """(module, service) pairs of the hello's interface: {"modules": {module: {service: kind}}, ...}."""
    modules = interface.get("modules")
    if not isinstance(modules, dict) or not modules:
        raise UntimelyError(f"the bench's hello has no interface modules: {json.dumps(interface)[:200]}")
    return [(module, service) for module, services in modules.items() for service in services]


def _text(path, key, value) -> str:
    if not isinstance(value, str) or not value:
        raise InputFileError(path, key, f"{key} = {value!r}; give a non-empty string")
    return value


def load_mapping(path: str | Path) -> Mapping:
    path = Path(path)
    data = read_toml(path, "mapping file not found; pass the ros.toml beside the interface")
    topic_keys = ("world_topic", "internal_topic", "ping_topic", "pong_topic")
    known = {"action", "services", "status_codes", "heartbeat_stale_s", *topic_keys}
    if set(data) - known:
        raise InputFileError(path, "", f"unknown key(s) {sorted(set(data) - known)}; it takes {', '.join(sorted(known))}")
    action = _text(path, "action", data.get("action", DEFAULT_ACTION))
    try:
        action.format(module="m", service="s")
    except (KeyError, IndexError, ValueError):
        raise InputFileError(path, "action", f"action = {action!r} may only use {{module}} and {{service}}") from None
    overrides = {}
    for service, name in (data.get("services") or {}).items():
        if service.count(".") != 1:
            raise InputFileError(path, f"[services] {service}", f"{service!r} is not \"module.Service\"")
        overrides[service] = parse_route(path, service, name)
    codes = dict(DEFAULT_STATUS_CODES)
    for status, code in (data.get("status_codes") or {}).items():
        if status not in TERMINAL_STATUSES:
            raise InputFileError(path, f"[status_codes] {status}",
                                 f"{status!r} is not a terminal goal status; use one of {', '.join(TERMINAL_STATUSES)}")
        codes[status] = _text(path, f"[status_codes] {status}", code)
    stale = data.get("heartbeat_stale_s", 1.0)
    if not isinstance(stale, (int, float)) or stale <= 0:
        raise InputFileError(path, "heartbeat_stale_s", f"heartbeat_stale_s = {stale!r}; give a positive number of seconds")
    topics = {key: _text(path, key, data[key]) if key in data else None for key in topic_keys}
    if (topics["ping_topic"] is None) != (topics["pong_topic"] is None):
        raise InputFileError(path, "ping_topic", "give both ping_topic and pong_topic, or neither")
    return Mapping(str(path), action, overrides, codes, float(stale), **topics)
