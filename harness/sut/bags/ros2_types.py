"""Message types of a rosbag2 bag's service and action introspection, built from their text.

rosbag2 stores, for a `<name>/_service_event` topic of type `pkg/srv/X_Event`, the service's own
`.srv` text (and for an action's events the `.action` text), which no message parser reads as
the event type: the stock high-level readers fail on them. So the bag is read raw, and the
types are built here as rosidl derives them: X_Request and X_Response from the two halves of
the .srv, X_Event = ServiceEventInfo + at most one request + at most one response; for an action
X_Goal/X_Result/X_Feedback, its SendGoal and GetResult services and X_FeedbackMessage. The
standard packages (action_msgs, service_msgs, unique_identifier_msgs) come from rosbags' Jazzy store.
"""
from __future__ import annotations

import re

from rosbags.typesys import Stores, get_types_from_msg, get_typestore

SEPARATOR = re.compile(r"^---\s*$", re.MULTILINE)
# the types rosidl derives from a service or action (the rest of a .srv's field types are messages)
DERIVED = re.compile(r"_(Request|Response|Event|Goal|Result|Feedback|FeedbackMessage|SendGoal\w*|GetResult\w*)$")


def typestore():
    return get_typestore(Stores.ROS2_JAZZY)


def _parsed(text: str, name: str) -> dict:
    """get_types_from_msg, with srv/action names kept (it files them under .../msg/), and a field's
    bare message type in a .srv or .action (lifecycle_msgs' `Transition transition`) resolved as
    rosidl does, to the package's msg/ folder (get_types_from_msg puts it beside the service)."""
    fix = lambda n: n.replace("/srv/msg/", "/srv/").replace("/action/msg/", "/action/")  # noqa: E731

    def fix_type(n: str) -> str:
        match = re.fullmatch(r"(\w+)/(?:srv|action)/(?:msg/)?(\w+)", n)
        return f"{match[1]}/msg/{match[2]}" if match and not DERIVED.search(match[2]) else fix(n)

    def fix_field(node):
        kind, rest = node
        if isinstance(rest, str):
            return kind, fix_type(rest)
        if isinstance(rest, tuple) and rest and isinstance(rest[0], tuple):
            return kind, (fix_field(rest[0]), *rest[1:])
        return node
    return {fix(n): (consts, [(f, fix_field(node)) for f, node in fields])
            for n, (consts, fields) in get_types_from_msg(text, name).items()}


def _service(types: dict, name: str, request: str, response: str) -> None:
    types.update(_parsed(request, f"{name}_Request"))
    types.update(_parsed(response, f"{name}_Response"))
    types.update(_parsed(f"service_msgs/msg/ServiceEventInfo info\n{name}_Request[<=1] request\n"
                         f"{name}_Response[<=1] response\n", f"{name}_Event"))


def service_types(name: str, text: str) -> dict:
    """The types of service `pkg/srv/X` from its .srv text."""
    parts = SEPARATOR.split(text)
    if len(parts) != 2:
        raise ValueError(f"the definition of {name} is no .srv text (request --- response)")
    types: dict = {}
    _service(types, name, *parts)
    return types


def action_types(name: str, text: str) -> dict:
    """The types of action `pkg/action/X` from its .action text."""
    parts = SEPARATOR.split(text)
    if len(parts) != 3:
        raise ValueError(f"the definition of {name} is no .action text (goal --- result --- feedback)")
    types: dict = {}
    for part, body in zip(("Goal", "Result", "Feedback"), parts):
        types.update(_parsed(body, f"{name}_{part}"))
    uuid = "unique_identifier_msgs/msg/UUID goal_id\n"
    _service(types, f"{name}_SendGoal", f"{uuid}{name}_Goal goal\n", "bool accepted\nbuiltin_interfaces/msg/Time stamp\n")
    _service(types, f"{name}_GetResult", uuid, f"int8 status\n{name}_Result result\n")
    types.update(_parsed(f"{uuid}{name}_Feedback feedback\n", f"{name}_FeedbackMessage"))
    return types


def register(store, msgtype: str, definition: str) -> None:
    """Make `msgtype` known to `store`: from its stored definition if that parses as one, else from
    the .srv or .action text it holds."""
    if msgtype in store.types:
        return
    match = re.fullmatch(r"(\w+)/(srv|action)/(\w+?)(_SendGoal_Event|_GetResult_Event|_FeedbackMessage|_Event)", msgtype)
    if match:
        package, kind, base, _ = match.groups()
        builder = service_types if kind == "srv" else action_types
        store.register(builder(f"{package}/{kind}/{base}", definition))
    else:
        store.register(get_types_from_msg(definition, msgtype))
