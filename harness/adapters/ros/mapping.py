"""The mapping file beside an interface (e.g. missions/dala/ros.toml): services -> actionlib actions,
goal statuses -> reply codes. Read by the generic adapter; no ROS import, so it can be checked anywhere."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, model_validator

from harness.errors import UntimelyError
from harness.files import read_toml
from harness.schema import Strict, cut, validated

# Terminal goal statuses that carry a reply (actionlib_msgs/GoalStatus names). LOST is not one:
# the client declared it, the server never ended the goal, so the adapter must not invent a final.
TERMINAL_STATUSES = ("SUCCEEDED", "ABORTED", "PREEMPTED", "REJECTED", "RECALLED")
DEFAULT_STATUS_CODES = {"SUCCEEDED": "ok", "ABORTED": "aborted", "PREEMPTED": "interrupted",
                        "REJECTED": "rejected", "RECALLED": "rejected"}
DEFAULT_ACTION = "/{module}"


@dataclass(frozen=True)
class Mapping:
    path: str
    action: str  # template of an action's name, from {module} and {service}
    overrides: dict[str, str]  # "module.Service" -> action name
    status_codes: dict[str, str]  # terminal status -> code when the result names none the catalogue knows
    heartbeat_stale_s: float  # a server whose last status is older than this (wall seconds) is not alive
    # Topics of std_msgs/String JSON, if the SUT has them; `stamp` is the instant's wall-clock epoch (time.time()).
    world_topic: str | None  # {stamp, kind, detail}: virtual damage
    internal_topic: str | None  # {goal_id, kind, code, stamp}: ground truth of each goal
    # {id}: the adapter publishes each ping on ping_topic; the SUT echoes it on pong_topic when alive
    ping_topic: str | None
    pong_topic: str | None

    def actions(self, services: list[tuple[str, str]]) -> dict[str, str]:
        """The action of each (module, service), by "module.Service". A goal names its service, not its
        module, so two services of one name may not share an action; every service needs one."""
        actions, served = {}, {}
        for module, service in services:
            qualified = f"{module}.{service}"
            if qualified in self.overrides:
                action = self.overrides[qualified]
            elif "{module}" in self.action:
                action = self.action.format(module=module, service=service)
            else:
                raise UntimelyError(f"{self.path}: no action for {qualified}; add it under [services], "
                                    "or make `action` a template with {module}")
            clash = served.setdefault((action, service), qualified)
            if clash != qualified:
                raise UntimelyError(f"{self.path}: {clash} and {qualified} both map to {action}, where a goal "
                                    "names only its service; give one of them another action")
            actions[qualified] = action
        return actions

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



TOPIC_HINT = "give a topic name such as \"/robot/world\""


class MappingFile(Strict):
    model_config = ConfigDict(title="a mapping file")
    action: str = Field(DEFAULT_ACTION, min_length=1, description="give an action name, or a template of "
                                                                  "{module} and {service}")
    services: dict[str, Annotated[str, Field(min_length=1)]] = Field(
        {}, description='give a table of "module.Service" = "/action"')
    status_codes: dict[Literal[TERMINAL_STATUSES], Annotated[str, Field(min_length=1)]] = Field(
        {}, description=f"give reply codes for terminal goal statuses: {', '.join(TERMINAL_STATUSES)}")
    heartbeat_stale_s: float = Field(1.0, gt=0, description="give a positive number of seconds")
    world_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    internal_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    ping_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)
    pong_topic: str | None = Field(None, min_length=1, description=TOPIC_HINT)

    @model_validator(mode="after")
    def _consistent(self):
        try:
            self.action.format(module="m", service="s")
        except (KeyError, IndexError, ValueError):
            raise ValueError(f"action = {cut(self.action)} may only use {{module}} and {{service}}") from None
        for service in self.services:
            if service.count(".") != 1:
                raise ValueError(f"services: {cut(service)} is not \"module.Service\"")
        if (self.ping_topic is None) != (self.pong_topic is None):
            raise ValueError("give both ping_topic and pong_topic, or neither")
        return self


def load_mapping(path: str | Path) -> Mapping:
    path = Path(path)
    data, text = read_toml(path, "mapping file not found; pass the ros.toml beside the interface")
    spec = validated(MappingFile, data, path, text)
    return Mapping(str(path), spec.action, dict(spec.services), {**DEFAULT_STATUS_CODES, **spec.status_codes},
                   spec.heartbeat_stale_s, spec.world_topic, spec.internal_topic, spec.ping_topic, spec.pong_topic)
