"""The target derived from a ROS 2 graph (harness/target/ros2_graph.py, ros2_texts.py), without ROS:
the graph is the JSON harness/sut/ros2/graph.py prints, written here by hand."""
import copy
import tomllib

import pytest

from harness.cli import main

from harness.sut.roscommon.mapping import load_mapping
from harness.errors import UntimelyError
from harness.target.interface import load_interface, load_properties
from harness.target.ros2_graph import derive
from harness.target.ros2_texts import golden_text, mapping_text, write
from harness.target.script import load_script, parse, validate

TRIGGER = {"success": "boolean", "message": "string"}


def endpoint(name, type_, fields=None, response=None):
    return {"name": name, "type": type_, "fields": {} if fields is None else fields, "response": response}


# The example's graph as graph.py reads it, infrastructure included (what the derivation leaves out)
GRAPH = {"nodes": [{"name": "/sequencer", "actions": [
    endpoint("/sequencer/countdown", "test_msgs/action/Fibonacci", {"order": "int32"}),
    endpoint("/sequencer/fibonacci", "test_msgs/action/Fibonacci", {"order": "int32"})], "services": [
    endpoint("/sequencer/calibrate", "std_srvs/srv/Trigger", {}, TRIGGER),
    endpoint("/sequencer/change_state", "lifecycle_msgs/srv/ChangeState", {"transition": "lifecycle_msgs/Transition"}),
    endpoint("/sequencer/fibonacci/_action/cancel_goal", "action_msgs/srv/CancelGoal", {"goal_info": "x/GoalInfo"}),
    endpoint("/sequencer/fibonacci/_action/send_goal", "test_msgs/action/Fibonacci_SendGoal", None),
    endpoint("/sequencer/get_parameters", "rcl_interfaces/srv/GetParameters", {"names": "sequence<string>"}),
    endpoint("/sequencer/get_state", "lifecycle_msgs/srv/GetState"),
    endpoint("/sequencer/get_type_description", "type_description_interfaces/srv/GetTypeDescription"),
    endpoint("/sequencer/reset", "std_srvs/srv/Trigger", {}, TRIGGER),
    endpoint("/sequencer/status", "std_srvs/srv/Trigger", {}, TRIGGER)]}]}
COMMAND = "python3 examples/ros2/sequencer.py"


@pytest.fixture
def written(tmp_path):
    target = derive(COMMAND, GRAPH)
    write(tmp_path / "t", target, {"jazzy": (), "kilted": ()}, tmp_path)
    return tmp_path / "t", target


def test_the_written_target_loads_and_its_golden_mission_uses_every_service(written):
    folder, target = written
    interface = load_interface(folder / "interface.toml")
    assert {name: s.kind for name, s in interface.services.items()} == {
        **{f"sequencer.{t}": "control" for t in ("configure", "cleanup", "activate", "deactivate", "shutdown")},
        "sequencer.countdown": "exec", "sequencer.fibonacci": "exec",
        "sequencer.countdown_cancel": "control", "sequencer.fibonacci_cancel": "control",
        "sequencer.calibrate": "control", "sequencer.reset": "control", "sequencer.status": "control"}
    order = interface.services["sequencer.fibonacci"].args["order"]
    assert (order.type, order.min, order.max) == ("float", -2 ** 31, 2 ** 31 - 1)  # int32's range
    golden = load_script(folder / "golden.mission", interface)
    sent = [step.service for step in golden.steps if step.op == "send"]
    assert sent[:2] == ["sequencer.configure", "sequencer.activate"]
    assert sent[-2:] == ["sequencer.deactivate", "sequencer.shutdown"]
    assert set(sent) == set(interface.services) - {"sequencer.cleanup", "sequencer.countdown_cancel",
                                                   "sequencer.fibonacci_cancel"}
    assert [step.args for step in golden.steps if step.service == "sequencer.fibonacci"] == [(("order", "10"),)]


def test_the_mapping_routes_every_service_and_tells_the_transitions_apart(written):
    folder, _ = written
    interface = load_interface(folder / "interface.toml")
    mapping = load_mapping(folder / "ros2.toml")
    routes = mapping.routes([(s.module, s.name) for s in interface.services.values()])
    assert routes["sequencer.activate"].name == routes["sequencer.configure"].name == "/sequencer/change_state"
    assert routes["sequencer.activate"].defaults == {"transition.id": 3}
    assert routes["sequencer.shutdown"].defaults == {"transition.label": "shutdown"}
    assert (routes["sequencer.fibonacci"].kind, routes["sequencer.fibonacci"].fields) == ("action", {"order": "order"})
    assert (routes["sequencer.reset"].success, routes["sequencer.reset"].failure) == ("success", "refused")
    assert routes["sequencer.activate"].failure == "transition_refused"
    assert (mapping.node, mapping.lifecycle, mapping.status_codes["REJECTED"]) == ("/sequencer", "mission", "rejected")


def test_every_action_gets_its_cancel_with_codes_the_catalogue_tells_apart(written):
    """init derives M.S_cancel for each action M.S: a control service routed to the action's
    cancel_goal, named in [cancels], its responses' codes in [cancel_codes]; every code the mapping
    can reply is in the catalogue, with ROS 2's outcomes in their classes."""
    folder, _ = written
    interface = load_interface(folder / "interface.toml")
    mapping = load_mapping(folder / "ros2.toml")
    assert mapping.cancels == {"sequencer.countdown_cancel": "sequencer.countdown",
                               "sequencer.fibonacci_cancel": "sequencer.fibonacci"}
    assert mapping.cancel_codes == {"ERROR_NONE": "ok", "ERROR_REJECTED": "cancel_rejected",
                                    "ERROR_UNKNOWN_GOAL_ID": "unknown_goal", "ERROR_GOAL_TERMINATED": "goal_terminated"}
    route = mapping.routes([("sequencer", "fibonacci_cancel")])["sequencer.fibonacci_cancel"]
    assert (route.kind, route.name, route.type) == ("service", "/sequencer/fibonacci/_action/cancel_goal",
                                                    "action_msgs/srv/CancelGoal")
    assert interface.replies == {"ok": "T", "aborted": "Z", "canceled": "Z", "rejected": "R", "refused": "R",
                                 "transition_refused": "R", "cancel_rejected": "R", "unknown_goal": "R",
                                 "goal_terminated": "R"}
    ros2_ends = ("SUCCEEDED", "ABORTED", "CANCELED", "REJECTED")  # PREEMPTED, RECALLED: ROS 1's
    replied = {*mapping.cancel_codes.values(), *(mapping.status_codes[status] for status in ros2_ends),
               *(r.failure for r in mapping.routes([(s.module, s.name) for s in interface.services.values()]).values()
                 if r.success)}
    assert replied <= set(interface.replies)
    script = parse("send sequencer.fibonacci order=3 as g\ncancel g as c\nwait c\n", "m")
    validate(script, interface)  # the derived interface runs the mission language's cancel


def test_the_properties_state_the_lifecycle_rules(written):
    folder, _ = written
    interface = load_interface(folder / "interface.toml")
    properties = {p.id: p for p in load_properties(folder / "properties.toml", interface)}
    goals = properties["ACTIVE_GOALS(sequencer)"]
    assert (goals.family, goals.type, goals.q, goals.y, goals.r_p) == (
        "ACTIVE", "IN", ("sequencer.activate",), ("sequencer.deactivate", "sequencer.shutdown"), "rejected")
    assert set(goals.x) == {"sequencer.countdown", "sequencer.fibonacci"}
    # a call answered while inactive is a defect only by the node's own rules: not derived, said how to add
    assert "ACTIVE_CALLS(sequencer)" not in properties
    assert 'copy this property as ACTIVE_CALLS with x = those calls and r_p = "refused"' in (
        folder / "properties.toml").read_text().replace("\n# ", " ")
    assert {p.r_p for p in properties.values() if p.family == "TRANSITION"} == {"transition_refused"}
    assert {(i, p.type) for i, p in properties.items() if p.family == "TRANSITION"} == {
        ("TRANSITION(sequencer.configure)", "OUT"), ("TRANSITION(sequencer.activate)", "IN"),
        ("TRANSITION(sequencer.cleanup)", "IN"), ("TRANSITION(sequencer.deactivate)", "IN"),
        ("TRANSITION(sequencer.shutdown)", "OUT")}
    text = (folder / "properties.toml").read_text()
    assert "lifecycle: activate is valid only from inactive" in text


ACTIONS = ("sequencer.countdown", "sequencer.fibonacci")
CANCELS = ("sequencer.countdown_cancel", "sequencer.fibonacci_cancel")
CALLS = ("sequencer.calibrate", "sequencer.reset", "sequencer.status")
TRANSITIONS = tuple(f"sequencer.{t}" for t in ("configure", "cleanup", "activate", "deactivate", "shutdown"))


def ros2_model(properties: dict) -> dict:
    """The properties of ROS 2's model of a node, as (type, x, y, z_p, r_p) with x and y as sets."""
    return {i: (p.type, set(p.x), set(p.y), p.z_p, p.r_p) for i, p in properties.items()
            if p.type in ("RSP", "CAN", "GOAL", "OUTLIVE")}


def test_a_lifecycle_node_gets_the_ros2_model_with_its_deadlines_left_to_the_golden_runs(written):
    folder, _ = written
    interface = load_interface(folder / "interface.toml")
    properties = {p.id: p for p in load_properties(folder / "properties.toml", interface)}
    assert ros2_model(properties) == {
        "RSP(sequencer)": ("RSP", {*CALLS, *CANCELS, *TRANSITIONS}, set(ACTIONS), None, None),
        **{f"CAN({a})": ("CAN", {f"{a}_cancel"}, {a}, "canceled", None) for a in ACTIONS},
        **{f"GOAL({a})": ("GOAL", {a}, set(), None, None) for a in ACTIONS},  # any rejection code enforces it
        "OUTLIVE(sequencer)": ("OUTLIVE", set(ACTIONS), {"sequencer.deactivate", "sequencer.cleanup",
                                                         "sequencer.shutdown"}, None, None)}
    assert all(p.deadline is None for p in properties.values())  # derived from the golden runs
    text = (folder / "properties.toml").read_text()
    assert "PREEMPT" not in text.replace("replaces the commented PREEMPT", ""), "GOAL supersedes the PREEMPT choice"
    comments = [block.split("\n[[property]]")[0].replace("\n# ", " ") for block in text.split("\n\n# ")[1:]]
    assert len(comments) == len(properties) and all("delete this [[property]]" in c for c in comments), comments
    flat = text.replace("\n# ", " ")  # the comments, unwrapped
    assert "as Nav2's action servers do" in flat and "in parallel, or queues them, by design" in flat


def test_a_plain_node_gets_responsiveness_cancels_and_one_goal_at_a_time(tmp_path):
    graph = copy.deepcopy(GRAPH)
    graph["nodes"][0]["services"] = [s for s in graph["nodes"][0]["services"] if "lifecycle" not in s["type"]]
    target = derive(COMMAND, graph)
    write(tmp_path / "t", target, {"jazzy": ()}, tmp_path)
    interface = load_interface(tmp_path / "t" / "interface.toml")
    properties = {p.id: p for p in load_properties(tmp_path / "t" / "properties.toml", interface)}
    assert ros2_model(properties) == {
        "RSP(sequencer)": ("RSP", {*CALLS, *CANCELS}, set(ACTIONS), None, None),
        **{f"CAN({a})": ("CAN", {f"{a}_cancel"}, {a}, "canceled", None) for a in ACTIONS},
        **{f"GOAL({a})": ("GOAL", {a}, set(), None, None) for a in ACTIONS}}
    assert set(properties) == set(ros2_model(properties)), "no lifecycle property for a plain node"
    golden = (tmp_path / "t" / "golden.mission").read_text()
    assert "configure" not in golden and "send sequencer.countdown order=10 as" in golden


def test_a_node_with_services_only_gets_responsiveness_and_a_node_without_any_none():
    services = {"nodes": [{"name": "/cam", "actions": [], "services": [
        endpoint("/cam/snap", "std_srvs/srv/Trigger", {}, TRIGGER)]}]}
    assert [(p["id"], p["x"], p["y"]) for p in derive("cam", services).properties] == [
        ("RSP(cam)", ["cam.snap"], [])]
    assert derive("idle", {"nodes": [{"name": "/idle", "actions": [], "services": []}]}).properties == []


@pytest.mark.parametrize(("field", "ros_type", "goal", "expected"), [
    ("order", "int32", True, "10"), ("count", "uint8", True, "10"), ("num_steps", "int64", True, "10"),
    ("batchSize", "int16", True, "10"), ("n", "int8", True, "10"), ("speed", "int32", True, "3"),
    ("border", "int32", True, "3"), ("order", "int32", False, "3"), ("order", "double", True, "1.0")])
def test_a_goals_count_field_makes_it_run_long_enough_to_matter(field, ros_type, goal, expected):
    """A goal's integer field named as a number of iterations gets LONG_RUN (the ROS 2 tutorial's
    order=10), clamped to its type; any other field, and any service's, keeps its small value."""
    kind = "actions" if goal else "services"
    node = {"name": "/n", "actions": [], "services": []}
    node[kind].append(endpoint("/n/go", "p/action/Go" if goal else "p/srv/Go", {field: ros_type}))
    (service,) = [s for s in derive("n", {"nodes": [node]}).services if not s.cancel]
    assert service.golden == {field: expected}


def test_one_sut_per_distro_runs_the_command_in_the_distros_environment(written, tmp_path):
    folder, _ = written
    text = (folder / "suts.toml").read_text()
    assert "[sequencer-jazzy]" in text and "[sequencer-kilted]" in text
    assert f"--distro kilted --mapping {{mission}}/ros2.toml -- bash -c 'cd {tmp_path} && exec {COMMAND}'" in text


def test_what_cannot_be_derived_is_said():
    graph = copy.deepcopy(GRAPH)
    node = graph["nodes"][0]
    node["services"] = [s for s in node["services"] if "lifecycle" not in s["type"]]
    node["actions"][0]["fields"] = {"order": "int32", "fast": "boolean", "path": "sequence<double>"}
    node["actions"][1]["fields"] = None
    target = derive(COMMAND, graph)
    assert not [p for p in target.properties if p["family"] in ("ACTIVE", "TRANSITION", "OUTLIVE")]
    golden = golden_text(target)
    assert "configure" not in golden and "every action and service once" in golden  # no lifecycle to speak of
    assert "\nlifecycle = false\n" in mapping_text(target) and "no lifecycle to reset it" in mapping_text(target)
    notes = "\n".join(target.notes)
    for words in ("/sequencer is not a lifecycle node", "field fast (boolean) is no argument",
                  "field path (sequence<double>) is no argument",
                  "/sequencer/fibonacci: its type test_msgs/action/Fibonacci could not be imported"):
        assert words in notes


def test_an_empty_or_malformed_graph_or_a_name_clash_is_refused(tmp_path):
    with pytest.raises(UntimelyError, match="started no ROS 2 node; check that it runs a node"):
        derive(COMMAND, {"nodes": []})
    with pytest.raises(UntimelyError, match="the ROS 2 graph read is malformed"):
        derive(COMMAND, {"nodes": [{"name": "/a"}]})
    clash = copy.deepcopy(GRAPH)
    clash["nodes"][0]["services"].append(endpoint("/status", "std_srvs/srv/Trigger", {}, TRIGGER))
    with pytest.raises(UntimelyError, match="/status and /sequencer/status both become sequencer.status; rename"):
        derive(COMMAND, clash)


def test_an_existing_target_file_is_never_overwritten(written):
    folder, target = written
    with pytest.raises(UntimelyError, match="already holds interface.toml.*give another DIR"):
        write(folder, target, {"jazzy": ()}, folder)


def test_init_takes_one_source_only(tmp_path, capsys):
    assert main(["init", str(tmp_path / "t"), "--from-genom", "x.gen", "--from-ros2", COMMAND]) == 2
    assert "give --from-genom or --from-ros2, not both" in capsys.readouterr().err
    assert not (tmp_path / "t").exists()


def test_interfaces_need_the_graph_and_not_a_bag_yet(tmp_path, capsys):
    assert main(["init", str(tmp_path / "t"), "--interfaces", "pkg"]) == 2
    assert "--interfaces pkg: give --from-ros2 'COMMAND' too" in capsys.readouterr().err
    assert main(["init", str(tmp_path / "t"), "--from-ros2", COMMAND, "--from-bag", "b", "--interfaces", "pkg"]) == 2
    assert "--interfaces with --from-bag is not supported yet" in capsys.readouterr().err
    assert not (tmp_path / "t").exists()


def test_each_suts_env_names_the_interfaces_built_for_its_distro(tmp_path):
    prefixes = {"jazzy": (tmp_path / "a" / "install", tmp_path / "b" / "install"), "kilted": (tmp_path / "k",)}
    write(tmp_path / "t", derive(COMMAND, GRAPH), prefixes, tmp_path)
    suts = tomllib.loads((tmp_path / "t" / "suts.toml").read_text())
    assert suts["sequencer-jazzy"]["env"] == {"UNTIMELY_ROS2_INTERFACES": f"{tmp_path}/a/install:{tmp_path}/b/install"}
    assert suts["sequencer-kilted"]["env"] == {"UNTIMELY_ROS2_INTERFACES": f"{tmp_path}/k"}
    written = derive(COMMAND, GRAPH)
    write(tmp_path / "plain", written, {"jazzy": ()}, tmp_path)
    assert "env" not in tomllib.loads((tmp_path / "plain" / "suts.toml").read_text())["sequencer-jazzy"]
