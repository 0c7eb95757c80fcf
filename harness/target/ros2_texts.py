"""The files of a target derived from a ROS 2 graph (harness/target/ros2_graph.py): interface.toml,
ros2.toml (the ROS 2 adapter's mapping, docs/ros2.md), suts.toml (one SUT per installed distro),
golden.mission and properties.toml, each commented with where it comes from."""
from __future__ import annotations

import json
import os
import shlex
from dataclasses import dataclass
from pathlib import Path

from harness.target.ros2_graph import CANCEL_CODES, REJECTED, REPLIES, Derived, Ros2Target
from harness.target.draft import WAIT_TIMEOUT_S, Draft, properties_text
from harness.target.mission import (GOLDEN_FILE, INTERFACE_FILE, PROPERTIES_FILE, ROS2_MAPPING_FILE,
                                     SUTS_FILE)
from harness.target.scaffold import write_all_or_none

# The install prefixes of a user's interface packages (os.pathsep-separated) in a SUT's env; every
# ROS 2 environment of the bench finds them (harness/sut/ros2/environment.py).
INTERFACES_VARIABLE = "UNTIMELY_ROS2_INTERFACES"
from harness.target.script import Step

WRITTEN = (INTERFACE_FILE, ROS2_MAPPING_FILE, SUTS_FILE, GOLDEN_FILE, PROPERTIES_FILE)
# The node's executor answers get_parameters within this, or the trace hangs: short enough that a
# node an invalid transition killed (rclpy#1209) is found hung within the executive's drain. A goal
# that blocks a single-threaded executor for longer ends its trace hung too (responsiveness FNs).
HEARTBEAT_STALE_S = 2.0


def value(item) -> str:
    """A TOML value: JSON's strings, numbers and booleans are TOML's; tables become inline tables."""
    if isinstance(item, dict):
        return "{ " + ", ".join(f"{json.dumps(k)} = {value(v)}" for k, v in item.items()) + " }" if item else "{}"
    if isinstance(item, (list, tuple)):
        return "[" + ", ".join(value(v) for v in item) + "]"
    return json.dumps(item)


def interface_text(target: Ros2Target) -> str:
    lines = [f"# The interface of the ROS 2 node(s) started by {target.command!r}, made by `untimely init",
             "# --from-ros2` from their graph (docs/ros2.md): a module per node; its action servers are exec",
             "# services, its services, each action's cancel (S_cancel) and lifecycle transitions (on",
             "# change_state) control services; the arguments are the goal's or request's number and string",
             "# fields, within their type's range.",
             "", "[replies]"]
    lines += [f'{code} = "{cls}"  # {meaning}' for code, (cls, meaning) in REPLIES.items()]
    for module in dict.fromkeys(s.module for s in target.services):
        lines += ["", f"[modules.{module}]"]
        for s in target.of(module):
            args = {a.name: {k: v for k, v in (("type", a.type), ("min", a.min), ("max", a.max)) if v is not None}
                    for a in s.args}
            lines.append(f"services.{s.name} = {value({'kind': s.kind, **({'args': args} if args else {})})}")
    return "\n".join(lines) + "\n"


def mapping_text(target: Ros2Target) -> str:
    node = next((n for n in target.nodes if n.managed), target.nodes[0])
    lines = ["# How the interface reaches ROS 2 (docs/ros2.md), made by `untimely init --from-ros2`.",
             "# Each service has its route: an action server, a service, or a lifecycle transition called on",
             *(["# change_state. The mission drives the lifecycle itself (lifecycle = \"mission\"): between runs",
                "# the adapter takes the node back to unconfigured, as it started, and the next run reuses it; a",
                "# node it cannot take back (shut down, a goal or call still unanswered) is started afresh. If",
                "# your node's cleanup leaves state behind, give lifecycle = false: every run starts it afresh."]
               if node.managed else
               ["# change_state. The node has no lifecycle to reset it (lifecycle = false): every run starts it",
                "# afresh."]),
             f"node = {value(node.name)}  # its executor must answer get_parameters, else the trace hangs",
             f"lifecycle = {value('mission') if node.managed else 'false'}", f"heartbeat_stale_s = {HEARTBEAT_STALE_S}", "",
             f"[status_codes]  # a goal's end: SUCCEEDED is ok; a rejected goal is {REJECTED}",
             'ABORTED = "aborted"', 'CANCELED = "canceled"', f'REJECTED = "{REJECTED}"']
    if target.cancels:
        lines += ["", "[cancels]  # a request of the first (a script's `cancel HANDLE`) cancels that goal of the second"]
        lines += [f"{value(cancel)} = {value(action)}" for cancel, action in target.cancels.items()]
        lines += ["", "[cancel_codes]  # a cancel's response (action_msgs/srv/CancelGoal) -> its reply code"]
        lines += [f"{name} = {value(code)}" for name, code in CANCEL_CODES.items()]
    lines += [line for s in target.services for line in ("", f'[services."{s.qualified}"]', *_route(s))]
    return "\n".join(lines) + "\n"


def _route(service: Derived) -> list[str]:
    return [f"{key} = {value(item)}" for key, item in service.route.items() if item or key != "fields"]


def suts_text(target: Ros2Target, distros: dict[str, tuple[Path, ...]], cwd: Path) -> str:
    """One SUT per distro (-> the install prefixes of the user's interface packages built for it):
    COMMAND run from `cwd` in the distro's environment (its python3 first on PATH)."""
    node = shlex.join(["bash", "-c", f"cd {shlex.quote(str(cwd))} && exec {target.command}"])
    lines = ["# The node(s) on each installed ROS 2 distro (docs/reference/suts.md): `--sut NAME`. The adapter",
             "# starts the command below in the distro's environment, as sourcing its setup.bash would (its",
             "# python3 first on PATH), in a ROS 2 domain of its own confined to this machine."]
    if any(distros.values()):
        lines.append(f"# {INTERFACES_VARIABLE}: your interface packages built for the distro (`init --interfaces`).")
    for distro, prefixes in distros.items():
        command = f"{{python}} -m harness.sut.ros2 --distro {distro} --mapping {{mission}}/ros2.toml -- {node}"
        lines += ["", f"[{_sut_name(target)}-{distro}]", f"command = {value(command)}",
                  "slots = 2", "time_scale = 1.0", "startup_s = 90.0", "probe_timeout_s = 5.0"]
        if prefixes:
            lines.append(f"env = {value({INTERFACES_VARIABLE: os.pathsep.join(str(p) for p in prefixes)})}")
    return "\n".join(lines) + "\n"


def _sut_name(target: Ros2Target) -> str:
    return "-".join(dict.fromkeys(s.module for s in target.services)).replace("_", "-") or "ros2"


def golden_text(target: Ros2Target) -> str:
    """Bring-up in a valid order, each action and service once, then deactivate and shutdown (the
    lifecycle steps only for a lifecycle node)."""
    managed = any(s.transition for s in target.services)
    lines = ["# The golden mission (docs/reference/mission-language.md), made by `untimely init --from-ros2`:",
             *(["# each lifecycle node configured and activated, every action and service once with well-formed",
                "# arguments (edit the values to your node's), then deactivated and shut down."] if managed else
               ["# every action and service once with well-formed arguments (edit the values to your node's)."]),
             "# A goal's count field (order, count, steps, size, ...) is 10, within its type: a goal that runs a",
             "# while, so that the focused tests' calls, cancels and second goals come while it executes.", ""]
    modules = list(dict.fromkeys(s.module for s in target.services))
    steps = [f"{m}.{t}" for m in modules for t in ("configure", "activate") if _has(target, m, t)]
    steps += [s for m in modules for s in target.of(m) if not (s.transition or s.cancel)]
    steps += [f"{m}.{t}" for m in modules for t in ("deactivate", "shutdown") if _has(target, m, t)]
    for step in steps:
        name, args = (step, "") if isinstance(step, str) else (step.qualified, "".join(
            f" {k}={v}" for k, v in step.golden.items()))
        handle = name.replace(".", "_")
        lines += [f"send {name}{args} as {handle}", f"wait {handle} timeout={WAIT_TIMEOUT_S}"]
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class Recorded:
    """A request of a recorded session (`init --from-bag`): when it was sent and answered (seconds
    from the bag's start; `final` None when the bag holds no final reply), the service and its
    arguments (argument -> text; None when the bag does not carry them)."""
    sent: float
    service: str
    args: dict[str, str] | None
    final: float | None


def recorded_golden_text(target: Ros2Target, requests: list[Recorded], source: str) -> str:
    """The recorded session as the golden mission: its requests in their order, with their
    arguments; a request sent after an earlier one's final reply waits for that reply first (so
    the replay keeps what the session showed: the next request followed the reply), and the rest
    of each gap between sends is a sleep."""
    golden = {s.qualified: s.golden for s in target.services}
    steps, pending, handles, last = [], [], {}, requests[0].sent if requests else 0.0
    for request in requests:
        for earlier in sorted((r for r in pending if r[0].final <= request.sent), key=lambda r: r[0].final):
            steps.append(Step(0, "wait", handle=earlier[1], seconds=WAIT_TIMEOUT_S))
            pending.remove(earlier)
            last = max(last, earlier[0].final)
        if round(request.sent - last, 3) > 0:
            steps.append(Step(0, "sleep", seconds=round(request.sent - last, 3)))
        last = request.sent
        count = handles[request.service] = handles.get(request.service, 0) + 1
        handle = f"{request.service.replace('.', '_')}_{count}"
        args = golden[request.service] if request.args is None else request.args
        comment = "arguments not in the bag: the derived values" if request.args is None and args else ""
        steps.append(Step(0, "send", request.service, tuple(args.items()), handle, comment=comment))
        if request.final is not None:
            pending.append((request, handle))
    steps += [Step(0, "wait", handle=handle, seconds=WAIT_TIMEOUT_S) for _, handle in pending]
    lines = [f"# The golden mission recorded in {source}, made by `untimely init --from-ros2 --from-bag`:",
             "# its requests in their order with their arguments; a request the session sent after an",
             "# earlier one's final reply waits for it, and the rest of each gap between sends is a sleep.", ""]
    return "\n".join(lines + [step.render() for step in steps]) + "\n"


def _has(target: Ros2Target, module: str, name: str) -> bool:
    return any(s.name == name and s.transition for s in target.of(module))


def properties_text_of(target: Ros2Target) -> str:
    """ROS 2's model of each node (harness/target/ros2_properties.py), each property commented with
    why it was derived and how to turn it off."""
    return properties_text(Draft(f"the ROS 2 graph of {target.command!r}", {}, target.properties),
                           "a basic type (PC, ES, EE, EX, MX_R, MX_I, VAL), IN, OUT or a ROS 2 type (RSP, CAN, GOAL, OUTLIVE)")


def write(folder: Path, target: Ros2Target, distros: dict[str, tuple[Path, ...]], cwd: Path,
          golden: str | None = None) -> list[Path]:
    """Write the target folder, all files or none; refuses to overwrite any file of it. `distros`:
    each installed distro -> the install prefixes of the user's interface packages built for it;
    `golden`: the golden mission's text (a recorded session's), else the derived one."""
    texts = {INTERFACE_FILE: interface_text(target), ROS2_MAPPING_FILE: mapping_text(target),
             SUTS_FILE: suts_text(target, distros, cwd), GOLDEN_FILE: golden or golden_text(target),
             PROPERTIES_FILE: properties_text_of(target)}
    return write_all_or_none(folder, texts, {})
