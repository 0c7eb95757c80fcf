"""The mapping file beside an interface (missions/dala/ros.toml for ROS 1, ros2.toml for ROS 2):
services -> actions or ROS services (routes.py), goal statuses -> reply codes. Read by the ROS 1
and ROS 2 adapters, their nodes and the bag importer; no ROS import, so it can be checked anywhere."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, model_validator

from harness.sut.roscommon.routes import GENERIC_SERVICE_TYPE, GENERIC_TYPE, Route, parse_route
from harness.errors import InputFileError, UntimelyError
from harness.files import read_toml
from harness.schema import Strict, cut, validated

# Terminal goal statuses that carry a reply: actionlib_msgs/GoalStatus names (ROS 1), and CANCELED,
# action_msgs/GoalStatus's name for a cancelled goal (ROS 2; its SUCCEEDED and ABORTED are ROS 1's,
# and REJECTED stands for a goal response that did not accept). LOST is not one: the client declared
# it, the server never ended the goal, so the adapter must not invent a final.
TERMINAL_STATUSES = ("SUCCEEDED", "ABORTED", "PREEMPTED", "REJECTED", "RECALLED", "CANCELED")
DEFAULT_STATUS_CODES = {"SUCCEEDED": "ok", "ABORTED": "aborted", "PREEMPTED": "interrupted",
                        "REJECTED": "rejected", "RECALLED": "rejected", "CANCELED": "interrupted"}
DEFAULT_ACTION = "/{module}"
# ROS 2: the return codes of a cancel request's response (action_msgs/srv/CancelGoal) and their
# default reply codes: ERROR_NONE, the goal is canceling; the others, the cancel is refused.
CANCEL_RESPONSES = ("ERROR_NONE", "ERROR_REJECTED", "ERROR_UNKNOWN_GOAL_ID", "ERROR_GOAL_TERMINATED")
CANCEL_SUFFIX = "_cancel"  # the mission language's `cancel HANDLE` requests SERVICE_cancel of the handle's module
DEFAULT_CANCEL_CODES = {"ERROR_NONE": "ok", "ERROR_REJECTED": "rejected", "ERROR_UNKNOWN_GOAL_ID": "rejected",
                        "ERROR_GOAL_TERMINATED": "rejected"}


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
    # a std_srvs/Trigger service that returns the SUT to its initial state: with it, one master,
    # node and adapter serve run after run (the adapter offers `reuse`)
    reset_service: str | None = None
    # ROS 2: template of the ROS service serving each `control` and `init` service (None: they are
    # goals of `action` too), and the node whose executor answers the liveness probe
    # (NODE/get_parameters) and, with lifecycle, whose transitions bring it up and reset it
    service: str | None = None
    node: str | None = None
    # true: the adapter brings the node up and resets it between runs; "mission": the mission drives
    # its transitions and the adapter takes it back to unconfigured between runs; false: no lifecycle
    lifecycle: bool | str = False
    # ROS 2: "module.Service" -> "module.Service" of the goals a request of it cancels, and the
    # reply code of each CancelGoal return code
    cancels: dict[str, str] = field(default_factory=dict)
    cancel_codes: dict[str, str] = field(default_factory=lambda: dict(DEFAULT_CANCEL_CODES))

    @property
    def folder(self) -> Path:
        """Where the routes' definition files are."""
        return Path(self.path).parent

    def routes(self, services: list[tuple[str, str]], kinds: dict[str, str] | None = None) -> dict[str, Route]:
        """The route of each (module, service), by "module.Service"; `kinds` ("module.Service" ->
        init, control or exec) places the non-exec ones on the `service` template. A generic goal
        names its service, not its module, so two services of one name may not share a generic
        action; a typed action or a ROS service names neither, so it serves one service only."""
        routes: dict[str, Route] = {}
        for module, service in services:
            qualified = f"{module}.{service}"
            if qualified in self.overrides:
                route = self.overrides[qualified]
            elif self.service and (kinds or {}).get(qualified) in ("init", "control"):
                route = Route("service", self.service.format(module=module, service=service), GENERIC_SERVICE_TYPE,
                              code="code")
            elif "{module}" in self.action:
                route = Route("action", self.action.format(module=module, service=service), GENERIC_TYPE)
            else:
                raise UntimelyError(f"{self.path}: no action for {qualified}; add it under [services], "
                                    "or make `action` a template with {module}")
            clash = next((other for other, known in routes.items() if known.name == route.name and not (
                route.generic and known.generic and other.split(".")[1] != service) and not _told_apart(route, known)),
                None)
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



def check_cancels(mapping: Mapping, interface: dict) -> dict[str, str]:
    """"module.Service" of each cancel -> the name of the action whose goals it cancels, once the
    mapping is checked against the hello's interface, so that a target whose cancels cannot be
    served is refused before any node starts (docs/ros2.md, "Cancels"): each [cancels] entry names
    two services of the interface, the second an action; a `SERVICE_cancel` of an action's SERVICE
    has a [cancels] entry (it would otherwise be a goal of its own); every [cancel_codes] code is
    in the interface's catalogue."""
    services = interface_services(interface)
    qualified = {f"{module}.{service}" for module, service in services}
    routes = mapping.routes([s for s in services if ".".join(s) not in mapping.cancels], interface_kinds(interface))
    targets = {}
    for canceller, target in mapping.cancels.items():
        for name in (canceller, target):
            if name not in qualified:
                raise InputFileError(mapping.path, f'[cancels] "{canceller}"', f"{name} is no service of the "
                                     "interface; name services of interface.toml, or add them there")
        if routes.get(target) is None or routes[target].kind != "action":
            raise InputFileError(mapping.path, f'[cancels] "{canceller}"', f"{target} is not served by an action, "
                                 "so it has no goal to cancel; name an action's service")
        targets[canceller] = routes[target].name
    for name, route in routes.items():
        cancel = f"{name}{CANCEL_SUFFIX}"
        if route.kind == "action" and cancel in qualified and cancel not in mapping.cancels | mapping.overrides:
            raise InputFileError(mapping.path, "[cancels]", f'{cancel} has no entry; add "{cancel}" = "{name}" '
                                 f"to [cancels] (a request of it cancels a goal of {name})")
    catalogue = interface.get("replies") or {}
    for response, code in mapping.cancel_codes.items() if targets else ():
        if code not in catalogue:
            raise InputFileError(mapping.path, f"[cancel_codes] {response}", f"{code!r} is not in the interface's "
                                 f"reply catalogue; give {response} a code of it, or add {code} to [replies]")
    return targets


def _told_apart(route: Route, other: Route) -> bool:
    """Two calls of one typed service whose fixed request fields differ (a lifecycle node's
    transitions on its change_state, each its own transition id) can be told apart."""
    return route.kind == other.kind == "service" and route.type == other.type and route.defaults != other.defaults


def interface_services(interface: dict) -> list[tuple[str, str]]:
    """(module, service) pairs of the hello's interface: {"modules": {module: {service: kind}}, ...}."""
    modules = interface.get("modules")
    if not isinstance(modules, dict) or not modules:
        raise UntimelyError(f"the bench's hello has no interface modules: {json.dumps(interface)[:200]}")
    return [(module, service) for module, services in modules.items() for service in services]


def interface_kinds(interface: dict) -> dict[str, str]:
    """"module.Service" -> its kind, from the hello's interface."""
    return {f"{module}.{service}": kind for module, services in interface["modules"].items()
            for service, kind in services.items()}


TOPIC_HINT = "give a topic name such as \"/robot/world\""


class MappingFile(Strict):
    model_config = ConfigDict(title="a mapping file")
    action: str = Field(DEFAULT_ACTION, min_length=1, description="give an action name, or a template of "
                                                                  "{module} and {service}")
    services: dict[str, Annotated[str, Field(min_length=1)] | dict] = Field(
        {}, description='give a table of "module.Service" = "/action" or a route table (docs/ros.md)')
    status_codes: dict[Literal[TERMINAL_STATUSES], Annotated[str, Field(min_length=1)]] = Field(
        {}, description=f"give reply codes for terminal goal statuses: {', '.join(TERMINAL_STATUSES)}")
    heartbeat_stale_s: float = Field(1.0, gt=0, description="give a positive number of seconds")
    world_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    internal_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    ping_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    pong_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    reset_service: str | None = Field(None, min_length=1, description="give the name of a std_srvs/Trigger "
                                      "service, such as \"/robot/reset\"")
    service: str | None = Field(None, min_length=1, description="give a ROS 2 service name template of "
                                "{module} and {service}, such as \"/robot/{module}/{service}\"")
    node: str | None = Field(None, pattern=r"^/[A-Za-z_][A-Za-z0-9_/]*$",
                             description="give the ROS 2 node's full name, such as \"/robot\"")
    lifecycle: bool | Literal["mission"] = Field(False, description=(
        "give true for a lifecycle node the adapter brings up and resets, \"mission\" for one the mission "
        "drives (the adapter takes it back to unconfigured between runs), else false"))
    cancels: dict[str, str] = Field({}, description='give a table of "module.Service" = "module.Service": a '
                                    "request of the first cancels the latest goal of the second (ROS 2)")
    cancel_codes: dict[Literal[CANCEL_RESPONSES], Annotated[str, Field(min_length=1)]] = Field(
        {}, description=f"give reply codes for cancel responses: {', '.join(CANCEL_RESPONSES)}")

    @model_validator(mode="after")
    def _consistent(self):
        for key, template in (("action", self.action), ("service", self.service or "")):
            try:
                template.format(module="m", service="s")
            except (KeyError, IndexError, ValueError):
                raise ValueError(f"{key} = {cut(template)} may only use {{module}} and {{service}}") from None
        if self.lifecycle and not self.node:
            shown = "true" if self.lifecycle is True else f'"{self.lifecycle}"'
            raise ValueError(f"lifecycle = {shown} needs node, the lifecycle node's name")
        for key, names in (("services", list(self.services)), ("cancels", [*self.cancels, *self.cancels.values()])):
            for service in names:
                if service.count(".") != 1:
                    raise ValueError(f"{key}: {cut(service)} is not \"module.Service\"")
        if (self.ping_topic is None) != (self.pong_topic is None):
            raise ValueError("give both ping_topic and pong_topic, or neither")
        return self


def load_mapping(path: str | Path) -> Mapping:
    path = Path(path)
    data, text = read_toml(path, "mapping file not found; pass the ros.toml beside the interface")
    spec = validated(MappingFile, data, path, text)
    return Mapping(str(path), spec.action, {service: parse_route(path, service, route) for service, route in spec.services.items()}, {**DEFAULT_STATUS_CODES, **spec.status_codes},
                   spec.heartbeat_stale_s, spec.world_topic, spec.internal_topic, spec.ping_topic, spec.pong_topic,
                   spec.reset_service, spec.service, spec.node, spec.lifecycle, spec.cancels,
                   {**DEFAULT_CANCEL_CODES, **spec.cancel_codes})
