"""A target derived from a ROS 2 graph (`untimely init DIR --from-ros2 COMMAND`, docs/ros2.md):
pure, no ROS import. harness/sut/ros2/init.py reads the graph with rclpy and hands it here
as the JSON harness/sut/ros2/graph.py prints; harness/target/ros2_texts.py writes the files.

What the graph states, and what follows from it:
- a module per node; an `exec` service per action server, a `control` service per service of the
  node's own (parameter, type-description, action-internal and lifecycle services left out);
- each action's goals can be cancelled: its cancel is a `control` service of its own, `S_cancel`
  beside the action's `S` (the mission language's `cancel HANDLE` sends it), routed to the action's
  cancel_goal service and named in ros2.toml's [cancels];
- a node serving lifecycle_msgs `change_state` and `get_state` is managed: its five transitions
  (configure, activate, deactivate, cleanup, shutdown) are `control` services (they answer at
  once), called on `change_state` by transition id (shutdown by its label, whose id depends on
  the state). Not `init`: the bench takes a module's init services as set-ups that every other
  service needs (GenoM's Init), while which transition comes when is what the properties state;
- the arguments of a goal or request are its fields of a number or string type, with the range
  of the type; other fields (booleans, sequences, nested messages) keep their defaults;
- the lifecycle's semantics (design article "Managed nodes") give the properties: no goal or call
  served unless active; each transition only from the states that offer it;
- the reply codes keep ROS 2's outcomes apart (docs/ros2.md, "Targets from the ROS 2 graph"):
  a goal rejected, a call answered success = false and a transition refused are three R codes, so a
  property's r_p is the code its requests really get; a goal the server aborts is interrupted (Z).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from harness.errors import UntimelyError
from harness.target.domains import Argument
from harness.target.script import CANCEL_SUFFIX

# The refusals of a goal, of a call (`success = false`) and of a transition, told apart.
REJECTED, REFUSED, TRANSITION_REFUSED = "rejected", "refused", "transition_refused"
# A cancel's response (action_msgs/srv/CancelGoal return codes) -> its reply code.
CANCEL_CODES = {"ERROR_NONE": "ok", "ERROR_REJECTED": "cancel_rejected", "ERROR_UNKNOWN_GOAL_ID": "unknown_goal",
                "ERROR_GOAL_TERMINATED": "goal_terminated"}
REPLIES = {"ok": ("T", "the goal succeeded, the call answered success, the transition was done, the cancel accepted"),
           "aborted": ("Z", "the server aborted the goal: a halt, a preemption or a deactivation interrupts it"),
           "canceled": ("Z", "the goal was canceled"),
           REJECTED: ("R", "the goal was rejected"),
           REFUSED: ("R", "the call answered success = false"),
           TRANSITION_REFUSED: ("R", "the transition was refused: invalid from this state, or its callback failed"),
           "cancel_rejected": ("R", "the cancel was rejected (ERROR_REJECTED)"),
           "unknown_goal": ("R", "the cancel named a goal the server does not know (ERROR_UNKNOWN_GOAL_ID)"),
           "goal_terminated": ("R", "the cancel came after the goal had ended (ERROR_GOAL_TERMINATED)")}
CANCEL_GOAL = "action_msgs/srv/CancelGoal"
# lifecycle_msgs/msg/Transition ids; shutdown goes by its label (its id depends on the state).
TRANSITIONS = {"configure": 1, "cleanup": 2, "activate": 3, "deactivate": 4, "shutdown": None}
# Each transition's source states as a span of IN or OUT (sql/oracles/in.sql, out.sql): the type,
# the transitions whose ok enters the span, those whose ok leaves it, and the rule in words.
FROM_STATES = {
    "configure": ("OUT", ["configure", "shutdown"], ["cleanup"], "only from unconfigured"),
    "activate": ("IN", ["configure", "deactivate"], ["activate", "cleanup", "shutdown"], "only from inactive"),
    "cleanup": ("IN", ["configure", "deactivate"], ["activate", "cleanup", "shutdown"], "only from inactive"),
    "deactivate": ("IN", ["activate"], ["deactivate", "shutdown"], "only from active"),
    "shutdown": ("OUT", ["shutdown"], [], "from any state but finalized"),
}
CHANGE_STATE = "lifecycle_msgs/srv/ChangeState"
INFRASTRUCTURE = re.compile(r"^(rcl_interfaces|type_description_interfaces|lifecycle_msgs)/")
INTEGERS = {f"{sign}int{bits}": (-(2 ** (bits - 1)) if sign == "" else 0, 2 ** (bits - (sign == "")) - 1)
            for sign in ("", "u") for bits in (8, 16, 32, 64)} | {"byte": (0, 255), "char": (0, 255), "octet": (0, 255)}
FLOATS = ("float", "double")
STRINGS = re.compile(r"^w?string(<=\d+)?$")


@dataclass(frozen=True)
class Endpoint:
    """A service or action server of the graph: full name, type, its request's or goal's fields
    and a service's response fields (name -> ROS type; None when the type could not be imported)."""
    name: str
    type: str
    fields: dict[str, str] | None
    response: dict[str, str] | None = None


@dataclass(frozen=True)
class NodeGraph:
    name: str
    services: tuple[Endpoint, ...]
    actions: tuple[Endpoint, ...]

    @property
    def managed(self) -> bool:
        types = {e.name: e.type for e in self.services}
        return (types.get(f"{self.name}/change_state") == CHANGE_STATE
                and types.get(f"{self.name}/get_state") == "lifecycle_msgs/srv/GetState")


@dataclass(frozen=True)
class Derived:
    """One service of the interface: its kind, arguments, golden values and ROS 2 route."""
    module: str
    name: str
    kind: str
    args: tuple[Argument, ...] = ()
    golden: dict[str, str] = field(default_factory=dict)  # argument -> a well-formed value
    route: dict = field(default_factory=dict)  # its [services] table of ros2.toml

    @property
    def qualified(self) -> str:
        return f"{self.module}.{self.name}"

    @property
    def transition(self) -> bool:
        return self.route.get("type") == CHANGE_STATE

    @property
    def cancel(self) -> bool:
        return self.route.get("type") == CANCEL_GOAL


@dataclass
class Ros2Target:
    command: str
    nodes: list[NodeGraph]
    services: list[Derived] = field(default_factory=list)
    properties: list[dict] = field(default_factory=list)  # [[property]] entries, "why" their comment
    notes: list[str] = field(default_factory=list)  # what could not be derived

    def of(self, module: str) -> list[Derived]:
        return [s for s in self.services if s.module == module]

    @property
    def cancels(self) -> dict[str, str]:
        """ros2.toml's [cancels]: each action's cancel service -> the action."""
        return {s.qualified: s.qualified[:-len(CANCEL_SUFFIX)] for s in self.services if s.cancel}


def graph_nodes(data: dict) -> list[NodeGraph]:
    """The graph's JSON (harness/sut/ros2/graph.py) as nodes; refuses one without a node."""
    def endpoints(entries) -> tuple[Endpoint, ...]:
        return tuple(Endpoint(e["name"], e["type"], e["fields"], e.get("response")) for e in entries)
    try:
        nodes = [NodeGraph(n["name"], endpoints(n["services"]), endpoints(n["actions"])) for n in data["nodes"]]
    except (KeyError, TypeError) as e:
        raise UntimelyError(f"the ROS 2 graph read is malformed ({e!r}): {str(data)[:200]}") from None
    if not nodes:
        raise UntimelyError("the command started no ROS 2 node; check that it runs a node (rclpy.init, spin)")
    return nodes


def identifier(text: str) -> str:
    """A name the mission language accepts: letters, digits and underscores, not starting with a digit."""
    name = re.sub(r"\W", "_", text.strip("/")) or "node"
    return name if not name[0].isdigit() else f"n{name}"


def short_name(node: NodeGraph, endpoint: Endpoint) -> str:
    prefix = node.name.rstrip("/") + "/"
    return identifier(endpoint.name[len(prefix):] if endpoint.name.startswith(prefix) else endpoint.name)


def arguments(endpoint: Endpoint, notes: list[str]) -> tuple[tuple[Argument, ...], dict[str, str], dict[str, str]]:
    """The arguments its fields give (the type's range), a well-formed value each, and the fields."""
    args, golden, fields = [], {}, {}
    if endpoint.fields is None:
        notes.append(f"{endpoint.name}: its type {endpoint.type} could not be imported in the distro's venv; "
                     "it takes no arguments here")
        return (), {}, {}
    for name, ros_type in endpoint.fields.items():
        if ros_type in INTEGERS:
            low, high = INTEGERS[ros_type]
            args.append(Argument(name, "float", float(low), float(high)))
            golden[name] = str(min(max(3, low), high))
        elif ros_type in FLOATS:
            args.append(Argument(name, "float"))
            golden[name] = "1.0"
        elif STRINGS.match(ros_type):
            args.append(Argument(name, "str"))
            golden[name] = "text"
        else:
            notes.append(f"{endpoint.name}: field {name} ({ros_type}) is no argument; it keeps its default value")
            continue
        fields[name] = name
    return tuple(args), golden, fields


def derive(command: str, data: dict) -> Ros2Target:
    """The target of the graph `data` that `command` brought up."""
    target = Ros2Target(command, graph_nodes(data))
    for node in target.nodes:
        module = identifier(node.name)
        if node.managed:
            target.services += [_transition(node, module, name, number) for name, number in TRANSITIONS.items()]
        for action in node.actions:
            args, golden, fields = arguments(action, target.notes)
            name = short_name(node, action)
            target.services.append(Derived(module, name, "exec", args, golden,
                                           {"action": action.name, "type": action.type, "fields": fields}))
            target.services.append(Derived(module, name + CANCEL_SUFFIX, "control", route={
                "service": f"{action.name}/_action/cancel_goal", "type": CANCEL_GOAL}))
        for service in node.services:
            if INFRASTRUCTURE.match(service.type) or "/_action/" in service.name:
                continue
            args, golden, fields = arguments(service, target.notes)
            route = {"service": service.name, "type": service.type, "fields": fields}
            # a response that says success (std_srvs/Trigger, SetBool) is ok or refused; any other is ok
            has_success = (service.response or {}).get("success") == "boolean"
            route.update({"success": "success", "failure": REFUSED} if has_success else {"failure": "ok"})
            target.services.append(Derived(module, short_name(node, service), "control", args, golden, route))
        _properties(target, node, module)
    _check_unique(target)
    return target


def _transition(node: NodeGraph, module: str, name: str, number: int | None) -> Derived:
    defaults = {"transition.id": number} if number is not None else {"transition.label": name}
    return Derived(module, name, "control", route={"service": f"{node.name}/change_state", "type": CHANGE_STATE,
                                                   "defaults": defaults, "success": "success",
                                                   "failure": TRANSITION_REFUSED})


# The requests a node serves only while active, by the code that refuses them (ACTIVE's r_p).
GATED = {"goals": (REJECTED, "its goals are rejected"), "calls": (REFUSED, "its calls answer success = false")}


def _properties(target: Ros2Target, node: NodeGraph, module: str) -> None:
    if not node.managed:
        target.notes.append(f"{node.name} is not a lifecycle node (no lifecycle_msgs change_state and get_state): "
                            "no lifecycle property; add yours to properties.toml")
        return
    served = {"goals": [s.qualified for s in target.of(module) if s.kind == "exec"],
              "calls": [s.qualified for s in target.of(module) if s.kind == "control" and not (s.transition or s.cancel)]}
    for what, (code, refusal) in GATED.items():
        if served[what]:
            target.properties.append({
                "id": f"ACTIVE_{what.upper()}({module})", "family": "ACTIVE", "type": "IN", "x": served[what],
                "q": [f"{module}.activate"], "y": [f"{module}.deactivate", f"{module}.shutdown"], "r_p": code,
                "why": (f"lifecycle (Managed nodes): a node does no processing unless active, so {refusal} "
                        "before activate and after deactivate or shutdown. Leave out of x what your node serves in "
                        "every state")})
    for name, (kind, enter, leave, words) in FROM_STATES.items():
        target.properties.append({
            "id": f"TRANSITION({module}.{name})", "family": "TRANSITION", "type": kind, "x": [f"{module}.{name}"],
            "q": [f"{module}.{t}" for t in enter], **({"y": [f"{module}.{t}" for t in leave]} if leave else {}),
            "r_p": TRANSITION_REFUSED,
            "why": (f"lifecycle: {name} is valid {words}; requested from another state it is refused (success = "
                    f"false: {TRANSITION_REFUSED}) and the node goes on serving (a node that stops answering makes the trace hung)")})


def _check_unique(target: Ros2Target) -> None:
    seen: dict[str, str] = {}
    for service in target.services:
        where = service.route.get("action") or service.route.get("service")
        if service.qualified in seen:
            raise UntimelyError(f"{where} and {seen[service.qualified]} both become {service.qualified}; rename one "
                                "of them in your node, or edit the written interface by hand")
        seen[service.qualified] = where
