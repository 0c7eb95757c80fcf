"""The properties `untimely init --from-ros2` derives for one node (docs/ros2.md, "The properties"):
from ROS 2's model of a node, never from what the node under test does (it may be wrong). Each
entry's "why" is its comment in properties.toml: the rule, where it comes from and how to turn it
off. The deadlines are left out: each is derived from the golden runs (docs/reference/verdicts.md,
"Deadlines"). Pure: it reads the node's derived services (harness/target/ros2_graph.py)."""
from __future__ import annotations

# The refusals of a goal, of a call (`success = false`) and of a transition, told apart.
REJECTED, REFUSED, TRANSITION_REFUSED = "rejected", "refused", "transition_refused"
CANCELED = "canceled"  # a goal's end once a client's cancel was accepted (GoalStatus STATUS_CANCELED)
# Each transition's source states as a span of IN or OUT (sql/oracles/in.sql, out.sql): the type,
# the transitions whose ok enters the span, those whose ok leaves it, and the rule in words.
FROM_STATES = {
    "configure": ("OUT", ["configure", "shutdown"], ["cleanup"], "only from unconfigured"),
    "activate": ("IN", ["configure", "deactivate"], ["activate", "cleanup", "shutdown"], "only from inactive"),
    "cleanup": ("IN", ["configure", "deactivate"], ["activate", "cleanup", "shutdown"], "only from inactive"),
    "deactivate": ("IN", ["activate"], ["deactivate", "shutdown"], "only from active"),
    "shutdown": ("OUT", ["shutdown"], [], "from any state but finalized"),
}
# The requests a node serves only while active, by the code that refuses them (ACTIVE's r_p): its
# goals. Not its calls: many a node answers queries (a status, a home check) in every state, and a
# call answered while inactive is no defect unless the node's own rules say so (the user adds it).
GATED = {"goals": (REJECTED, "its goals are rejected")}
CALLS_GATED = ("Its calls are not gated by default (many a node answers queries in every state): if "
               f"yours must answer success = false unless active, copy this property as ACTIVE_CALLS with x = "
               f"those calls and r_p = \"{REFUSED}\". ")
LEAVING = ("deactivate", "cleanup", "shutdown")  # the transitions that leave the active state behind
OFF = "delete this [[property]] to turn it off"


def properties_of(module: str, services: list, managed: bool) -> list[dict]:
    """The [[property]] entries of the node `module` whose derived services are `services`."""
    goals = [s.qualified for s in services if s.kind == "exec"]
    cancels = [s.qualified for s in services if s.cancel]
    transitions = [s.qualified for s in services if s.transition]
    calls = [s.qualified for s in services if s.kind == "control" and not (s.transition or s.cancel)]
    found = _responsive(module, calls + cancels + transitions, goals)
    found += [_cancel_honoured(goal) for goal in goals] + [_one_goal(goal) for goal in goals]
    if managed:
        found += _gated(module, {"goals": goals}) + _transitions(module)
        found += [_outlived(module, goals)] if goals else []
    return found


def _responsive(module: str, answered: list[str], goals: list[str]) -> list[dict]:
    if not answered:
        return []
    return [{"id": f"RSP({module})", "family": "RSP", "type": "RSP", "x": answered, "y": goals,
             "why": ("responsiveness: a ROS 2 node answers its calls, its goals' cancels and its transitions "
                     "while its goals execute (a callback that runs a goal to its end on a single-threaded "
                     "executor blocks them: give the goal a thread, or a reentrant callback group). The deadline: "
                     "10 times their largest latency in the golden runs, at least 1 s; set `deadline = SECONDS` "
                     f"to fix it. Leave out of x a request your node may answer late, or {OFF}")}]


def _cancel_honoured(goal: str) -> dict:
    return {"id": f"CAN({goal})", "family": "CAN", "type": "CAN", "x": [f"{goal}_cancel"], "y": [goal],
            "z_p": CANCELED,
            "why": (f"cancel honoured: ROS 2 actions are cancellable, so a cancel of an executing {goal} goal is "
                    f"accepted and the goal ends {CANCELED} within the deadline (derived from the golden runs), and "
                    "a cancel of an ended goal is refused (rclcpp#1569). A server whose cancel_callback rejects "
                    f"cancels by design: {OFF}")}


def _one_goal(goal: str) -> dict:
    return {"id": f"GOAL({goal})", "family": "GOAL", "type": "GOAL", "x": [goal],
            "why": (f"one goal at a time: a new {goal} goal while one executes is rejected, or preempts it (the "
                    "executing goal ends before the new one moves), as Nav2's action servers do; any rejection "
                    "code counts (add `r_p = \"rejected\"` to require the goal's). It replaces the commented "
                    "PREEMPT (EE) choice of earlier inits: either policy passes. A server that runs goals in "
                    f"parallel, or queues them, by design breaks it: {OFF}")}


def _gated(module: str, served: dict[str, list[str]]) -> list[dict]:
    return [{"id": f"ACTIVE_{what.upper()}({module})", "family": "ACTIVE", "type": "IN", "x": served[what],
             "q": [f"{module}.activate"], "y": [f"{module}.deactivate", f"{module}.shutdown"], "r_p": code,
             "why": (f"lifecycle (Managed nodes): a node does no processing unless active, so {refusal} "
                     f"before activate and after deactivate or shutdown. {CALLS_GATED}Leave out of x what your "
                     f"node serves in every state, or {OFF}")}
            for what, (code, refusal) in GATED.items() if served[what]]


def _transitions(module: str) -> list[dict]:
    return [{"id": f"TRANSITION({module}.{name})", "family": "TRANSITION", "type": kind, "x": [f"{module}.{name}"],
             "q": [f"{module}.{t}" for t in enter], **({"y": [f"{module}.{t}" for t in leave]} if leave else {}),
             "r_p": TRANSITION_REFUSED,
             "why": (f"lifecycle: {name} is valid {words}; requested from another state it is refused (success = "
                     f"false: {TRANSITION_REFUSED}) and the node goes on serving (a node that stops answering "
                     f"makes the trace hung). If your node offers it from more states, {OFF}")}
            for name, (kind, enter, leave, words) in FROM_STATES.items()]


def _outlived(module: str, goals: list[str]) -> dict:
    return {"id": f"OUTLIVE({module})", "family": "OUTLIVE", "type": "OUTLIVE", "x": goals,
            "y": [f"{module}.{t}" for t in LEAVING],
            "why": ("nothing outlives the state (Managed nodes): after an ok of deactivate, cleanup or shutdown "
                    "no goal still executes a deadline later (derived from how fast the node changes state in the "
                    "golden runs): the node aborts or cancels its goals as it leaves the active state "
                    "(ros2_controllers#1517). Leave out of x a goal your node finishes after deactivating by "
                    f"design; {OFF.lower()}")}
