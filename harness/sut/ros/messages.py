"""Message classes of the routes' types: from Debian's packages, or generated from .action or .srv text.

Debian ships ROS 1's Python libraries and some message packages (`python3-move-base-msgs`,
`python3-std-srvs`...) but no catkin workspace to build others in. A type whose package imports
is taken from it; an action or service whose package is missing is generated when it is first
needed, from its text (a route's `definition` file, or untimely_msgs/Request.action beside this
module), by genpy's dynamic generator (the one rosbag uses for types it has no package for). An
action's seven messages are what `genaction.py` derives from an .action file; a service's request
and response are the two halves of its .srv file, and its MD5 sum is genmsg's, as gensrv computes
it. Both ends generate them from the same text, so their MD5 sums agree on the wire (and agree
with a package built by catkin from that text).
"""
from __future__ import annotations

import functools
import importlib
import re
from pathlib import Path
from types import SimpleNamespace

import genmsg
import genmsg.msg_loader
import genpy.dynamic

from harness.sut.roscommon.routes import GENERIC_TYPE, Route
from harness.errors import UntimelyError

SEPARATOR = "\n" + "=" * 80 + "\n"
GENERIC_DEFINITION = Path(__file__).with_name("untimely_msgs") / "Request.action"
BUILTIN = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
           "float32", "float64", "string", "time", "duration"}


def _class(full_type: str, kind: str = "msg"):
    package, name = full_type.split("/")
    try:
        return getattr(importlib.import_module(f"{package}.{kind}"), name)
    except (ImportError, AttributeError):
        return None


def action_sections(full_type: str, text: str) -> dict[str, str]:
    """The seven messages of an .action text, by name, as genaction.py writes them."""
    package, name = full_type.split("/")
    parts = re.split(r"^---\s*$", text, flags=re.MULTILINE)
    if len(parts) != 3:
        raise UntimelyError(f"the definition of {full_type} has {len(parts)} parts; an .action file has goal, "
                            "result and feedback separated by two lines of ---")
    goal, result, feedback = parts
    return {f"{name}Action": f"{name}ActionGoal action_goal\n{name}ActionResult action_result\n"
                             f"{name}ActionFeedback action_feedback\n",
            f"{name}ActionGoal": f"Header header\nactionlib_msgs/GoalID goal_id\n{name}Goal goal\n",
            f"{name}ActionResult": f"Header header\nactionlib_msgs/GoalStatus status\n{name}Result result\n",
            f"{name}ActionFeedback": f"Header header\nactionlib_msgs/GoalStatus status\n{name}Feedback feedback\n",
            f"{name}Goal": goal, f"{name}Result": result, f"{name}Feedback": feedback}


def dependencies(package: str, texts) -> dict[str, str]:
    """`MSG:` sections of every type the texts use from other packages (Debian's classes carry
    their own dependencies' text in _full_text)."""
    sections: dict[str, str] = {}
    for text in texts:
        for line in text.splitlines():
            field_type = re.sub(r"\[\d*\]$", "", line.split("#")[0].split()[0]) if line.split("#")[0].split() else ""
            if not field_type or field_type in BUILTIN or "=" in line.split("#")[0]:
                continue
            full = "std_msgs/Header" if field_type == "Header" else field_type
            if "/" not in full or full.startswith(f"{package}/") or full in sections:
                continue
            message_class = _class(full)
            if message_class is None:
                raise UntimelyError(f"{full} is used by a {package} definition but no installed package has it")
            own, *rest = message_class._full_text.split(SEPARATOR)
            sections[full] = own
            for section in rest:
                label, _, body = section.partition("\n")
                sections.setdefault(label.removeprefix("MSG: ").strip(), body)
    return sections


def _definition(full_type: str, definition: Path) -> str:
    try:
        return definition.read_text()
    except OSError as e:
        raise UntimelyError(f"cannot read the definition of {full_type} ({definition}): {e}") from None


@functools.cache
def generated_action(full_type: str, definition: Path):
    """The action classes generated from an .action file."""
    text = _definition(full_type, definition)
    package, name = full_type.split("/")
    own = action_sections(full_type, text)
    sections = [own[f"{name}Action"]] + [f"MSG: {package}/{n}\n{t}" for n, t in own.items() if n != f"{name}Action"]
    sections += [f"MSG: {t}\n{body}" for t, body in dependencies(package, own.values()).items()]
    classes = genpy.dynamic.generate_dynamic(f"{package}/{name}Action", SEPARATOR.join(sections))
    return SimpleNamespace(**{part: classes[f"{package}/{name}{part}"]
                              for part in ("Action", "Goal", "Result", "Feedback", "ActionGoal", "ActionResult",
                                           "ActionFeedback")})


@functools.cache
def generated_service(full_type: str, definition: Path):
    """The service class generated from a .srv file: its _request_class, _response_class and
    the service's MD5 sum, which covers both halves."""
    text = _definition(full_type, definition)
    package, name = full_type.split("/")
    parts = re.split(r"^---\s*$", text, flags=re.MULTILINE)
    if len(parts) != 2:
        raise UntimelyError(f"the definition of {full_type} ({definition}) has {len(parts)} parts; a .srv file "
                            "has a request and a response separated by one line of ---")
    used = dependencies(package, parts)
    sections = [parts[0]] + [f"MSG: {package}/{name}Response\n{parts[1]}"]
    sections += [f"MSG: {t}\n{body}" for t, body in used.items()]
    classes = genpy.dynamic.generate_dynamic(f"{package}/{name}Request", SEPARATOR.join(sections))
    context = genmsg.MsgContext.create_default()
    for used_type, body in used.items():
        context.register(used_type, genmsg.msg_loader.load_msg_from_string(context, body, used_type))
    spec = genmsg.msg_loader.load_srv_from_string(context, text, full_type)
    return type(name, (), {"_type": full_type, "_md5sum": genmsg.compute_md5(context, spec),
                           "_request_class": classes[f"{package}/{name}Request"],
                           "_response_class": classes[f"{package}/{name}Response"]})


def _package_hint(full_type: str, kind: str) -> str:
    return (f"no message package has the {kind} {full_type}; install its Debian package "
            f"(python3-{full_type.split('/')[0].replace('_', '-')}) or give its .{'srv' if kind == 'service' else kind} "
            "file as the route's definition")


def action_classes(route: Route, mapping_dir: Path | None = None):
    """Namespace of Action, Goal, Result, Feedback (and the Action* wrappers) for an action route."""
    if route.generic:
        return generated_action(GENERIC_TYPE, GENERIC_DEFINITION)
    package_classes = {part: _class(f"{route.type}{part}") for part in
                       ("Action", "Goal", "Result", "Feedback", "ActionGoal", "ActionResult", "ActionFeedback")}
    if all(package_classes.values()):
        return SimpleNamespace(**package_classes)
    if route.definition and mapping_dir is not None:
        return generated_action(route.type, (mapping_dir / route.definition).resolve())
    raise UntimelyError(_package_hint(route.type, "action"))


def service_class(route: Route, mapping_dir: Path | None = None):
    """The service class (with _request_class and _response_class) of a ROS service route."""
    found = _class(route.type, "srv")
    if found is not None:
        return found
    if route.definition and mapping_dir is not None:
        return generated_service(route.type, (mapping_dir / route.definition).resolve())
    raise UntimelyError(_package_hint(route.type, "service"))


INTEGERS = {"byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"}


def _typed(value, slot_type: str, where: str):
    """An argument's value (text or a JSON number) as the field's type."""
    try:
        if slot_type in ("float32", "float64"):
            return float(value)
        if slot_type in INTEGERS:
            return int(float(value))
        if slot_type == "bool":
            return value if isinstance(value, bool) else str(value).lower() in ("true", "1", "yes")
        if slot_type == "string":
            return str(value)
    except (TypeError, ValueError):
        raise UntimelyError(f"{value!r} cannot fill {where}, a {slot_type}") from None
    raise UntimelyError(f"{where} is a {slot_type}; only numbers, bool and string fields take an argument")


def _set(message, path: str, value, type_name: str) -> None:
    *parents, last = path.split(".")
    for name in parents:
        message = getattr(message, name)
    slots = dict(zip(message.__slots__, message._slot_types))
    if last not in slots:
        raise UntimelyError(f"{type_name} has no field {path}; check the route's fields and defaults in ros.toml")
    setattr(message, last, _typed(value, slots[last], f"{type_name} field {path}"))


def fill(message, route: Route, args: dict):
    """A goal or request: the route's defaults, then the request's arguments in their fields."""
    for path, value in route.defaults.items():
        _set(message, path, value, route.type)
    for argument, value in args.items():
        if argument not in route.fields:
            raise UntimelyError(f"argument {argument}={value!r} has no field in {route.type}; add it to the route's "
                                "fields in ros.toml")
        _set(message, route.fields[argument], value, route.type)
    return message


# The generic action, which the Dala node and the adapter use by default.
_generic = generated_action(GENERIC_TYPE, GENERIC_DEFINITION)
RequestAction, RequestGoal, RequestResult, RequestFeedback = (_generic.Action, _generic.Goal, _generic.Result,
                                                               _generic.Feedback)
