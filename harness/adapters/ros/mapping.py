"""The mapping file beside an interface (e.g. missions/dala/ros.toml): services -> actionlib actions,
goal statuses -> reply codes. Read by the generic adapter; no ROS import, so it can be checked anywhere."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from harness.errors import InputFileError
from harness.interface import read_toml

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
    world_topic: str | None  # std_msgs/String of JSON {t, kind, detail}: virtual damage, if the SUT has any
    internal_topic: str | None  # std_msgs/String of JSON {goal_id, kind, t}: ground truth, if the SUT has any

    def action_of(self, module: str, service: str) -> str:
        return self.overrides.get(f"{module}.{service}") or self.action.format(module=module, service=service)

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

    def unmapped(self, services: list[str]) -> list[str]:
        """The services (of an interface) this mapping names no action for; empty for a template."""
        return [] if "{module}" in self.action else [s for s in services if s not in self.overrides]


def _text(path, key, value) -> str:
    if not isinstance(value, str) or not value:
        raise InputFileError(path, key, f"{key} = {value!r}; give a non-empty string")
    return value


def load_mapping(path: str | Path) -> Mapping:
    path = Path(path)
    data = read_toml(path, "mapping file not found; pass the ros.toml beside the interface")
    known = {"action", "services", "status_codes", "heartbeat_stale_s", "world_topic", "internal_topic"}
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
        overrides[service] = _text(path, f"[services] {service}", name)
    codes = dict(DEFAULT_STATUS_CODES)
    for status, code in (data.get("status_codes") or {}).items():
        if status not in TERMINAL_STATUSES:
            raise InputFileError(path, f"[status_codes] {status}",
                                 f"{status!r} is not a terminal goal status; use one of {', '.join(TERMINAL_STATUSES)}")
        codes[status] = _text(path, f"[status_codes] {status}", code)
    stale = data.get("heartbeat_stale_s", 1.0)
    if not isinstance(stale, (int, float)) or stale <= 0:
        raise InputFileError(path, "heartbeat_stale_s", f"heartbeat_stale_s = {stale!r}; give a positive number of seconds")
    topics = {key: _text(path, key, data[key]) if key in data else None for key in ("world_topic", "internal_topic")}
    return Mapping(str(path), action, overrides, codes, float(stale), **topics)
