"""The ROS mapping file (missions/dala/ros.toml): actions of services, codes of goal statuses. No ROS needed."""
import pytest

from harness import DEFAULT_MISSION_DIR
from harness.sut.roscommon.mapping import load_mapping
from harness.errors import InputFileError, UntimelyError

DALA = load_mapping(DEFAULT_MISSION_DIR / "ros.toml")


def write(tmp_path, text):
    path = tmp_path / "ros.toml"
    path.write_text(text)
    return path


def test_every_dala_service_goes_to_its_module_server(interface):
    actions = {q: r.name for q, r in DALA.routes([(s.module, s.name) for s in interface.services.values()]).items()}
    assert set(actions) == set(interface.services)
    assert actions["ndd.GotoPosition"] == actions["ndd.Stop"] == "/dala/ndd"
    assert sorted(set(actions.values())) == [f"/dala/{m}" for m in sorted(interface.modules)]


@pytest.mark.parametrize("status, texts, code", [
    ("SUCCEEDED", ("interrupted", "interrupted"), "ok"),  # SUCCEEDED is ok whatever its text
    ("ABORTED", ("goal_unreachable", ""), "goal_unreachable"),
    ("ABORTED", ("", "link_lost"), "link_lost"),  # no result code: the status text, when catalogued
    ("ABORTED", ("segfault", "segfault"), "aborted"),  # unknown to the catalogue: the fallback
    ("PREEMPTED", ("", ""), "interrupted"),
    ("PREEMPTED", ("interrupted_excl", "interrupted_excl"), "interrupted_excl"),
    ("REJECTED", ("wait_init", "wait_init"), "wait_init"),
    ("REJECTED", (None, ""), "rejected"),
    ("RECALLED", ("", ""), "rejected"),
    ("LOST", ("", ""), None),  # the client gave up on the goal: no final may be invented
    ("ACTIVE", ("", ""), None),
])
def test_a_goal_status_gives_a_catalogue_code_or_none(interface, status, texts, code):
    assert DALA.final_code(status, texts, interface.replies) == code


def test_fallback_codes_and_single_actions_come_from_the_file(tmp_path):
    mapping = load_mapping(write(tmp_path, 'action = "/robot/{module}/{service}"\n'
                                           '[services]\n"nav.Go" = "/move_base"\n'
                                           '[status_codes]\nABORTED = "failed"\n'))
    routes = mapping.routes([("nav", "Go"), ("nav", "Stop")])
    assert {q: r.name for q, r in routes.items()} == {"nav.Go": "/move_base", "nav.Stop": "/robot/nav/Stop"}
    assert mapping.final_code("ABORTED", ("boom",), {"ok": "T", "failed": "T"}) == "failed"
    assert mapping.world_topic is None and mapping.internal_topic is None


@pytest.mark.parametrize("text, message", [
    ('actions = "/x"\n', "ros.toml:1: unknown key 'actions'; a mapping file takes action, services"),
    ('action = "/{robot}"\n', "may only use {module} and {service}"),
    ('[status_codes]\nLOST = "lost"\n', "ros.toml:2: status_codes: key 'LOST' is not allowed; give 'SUCCEEDED', 'ABORTED'"),
    ('[status_codes]\nABORTED = ""\n', "give a non-empty string"),
    ('heartbeat_stale_s = 0\n', "heartbeat_stale_s = 0; give a positive number"),
    ('[services]\nGotoPosition = "/x"\n', "'GotoPosition' is not \"module.Service\""),
    ('ping_topic = "/ping"\n', "give both ping_topic and pong_topic, or neither"),
    ('heartbeat_stale_s = nan\n', "ros.toml:1: heartbeat_stale_s = nan; give a positive number of seconds"),
    ('[services]\n"nav.Go" = ["/x"]\n', "ros.toml:2: services.nav.Go = ['/x']; give a valid string"),
    ('world_topic = 5\n', "ros.toml:1: world_topic = 5; give a topic name"),
    ('lifecycle = true', "lifecycle = true needs node"),  # ROS 2's keys
    ('lifecycle = "mission"', 'lifecycle = "mission" needs node'),
    ('lifecycle = "sometimes"\nnode = "/n"', "lifecycle = 'sometimes'"),
    ('node = "dala"', "node = 'dala'"),
    ('service = "/x/{unit}"', "service = '/x/{unit}' may only use {module} and {service}"),
])
def test_a_bad_mapping_file_is_named_with_its_value(tmp_path, text, message):
    with pytest.raises(InputFileError, match="ros.toml") as e:
        load_mapping(write(tmp_path, text))
    assert message in str(e.value)


def test_services_a_mapping_cannot_tell_apart_are_refused(tmp_path):
    fixed = load_mapping(write(tmp_path, 'action = "/all"\n'))
    with pytest.raises(UntimelyError, match=r"no action for rflex.Init; add it under \[services\]"):
        fixed.routes([("rflex", "Init")])
    by_service = load_mapping(write(tmp_path, 'action = "/{service}"\n[services]\n"sick.Init" = "/Init"\n"rflex.Init" = "/Init"\n'))
    with pytest.raises(UntimelyError, match="sick.Init and rflex.Init both map to /Init"):
        by_service.routes([("sick", "Init"), ("rflex", "Init")])


def test_a_lifecycle_the_mission_drives_is_its_own_value(tmp_path):
    assert load_mapping(write(tmp_path, 'node = "/arm"\nlifecycle = "mission"\n')).lifecycle == "mission"
    assert load_mapping(write(tmp_path, 'node = "/arm"\nlifecycle = true\n')).lifecycle is True


def test_a_missing_mapping_file_says_what_to_pass(tmp_path):
    with pytest.raises(InputFileError, match="mapping file not found; pass the ros.toml beside the interface"):
        load_mapping(tmp_path / "nope.toml")


def test_typed_routes_name_their_types_fields_and_defaults(interface):
    typed = load_mapping(DEFAULT_MISSION_DIR / "ros-typed.toml")
    routes = typed.routes([(s.module, s.name) for s in interface.services.values()])
    goto, init, stop = routes["ndd.GotoPosition"], routes["ndd.Init"], routes["ndd.Stop"]
    assert (goto.kind, goto.name, goto.type) == ("action", "/move_base", "move_base_msgs/MoveBase")
    assert goto.fields == {"x": "target_pose.pose.position.x", "y": "target_pose.pose.position.y"}
    assert goto.defaults["target_pose.header.frame_id"] == "map"
    assert (init.kind, init.type, init.code, init.success) == ("service", "std_srvs/Trigger", "message", "success")
    assert stop.generic and stop.name == "/dala/ndd"


class Response:
    def __init__(self, success, message):
        self.success, self.message = success, message


@pytest.mark.parametrize("success, message, code", [
    (False, "wait_init", "wait_init"),  # the catalogue's code, whatever success says
    (True, "", "ok"),
    (True, "done", "ok"),
    (False, "motor fault", "failure"),
])
def test_a_service_response_gives_its_code_or_ok_or_failure(interface, success, message, code):
    init = load_mapping(DEFAULT_MISSION_DIR / "ros-typed.toml").overrides["ndd.Init"]
    assert init.response_code(Response(success, message), interface.replies) == code


@pytest.mark.parametrize("text, message", [
    ('[services."a.B"]\naction = "/x"\nservice = "/y"\n', "give exactly one of action = NAME or service = NAME"),
    ('[services."a.B"]\nservice = "/y"\n', "type = ''; give a non-empty string"),
    ('[services."a.B"]\naction = "/x"\ntype = "MoveBase"\n', "type = 'MoveBase' is not \"package/Name\""),
    ('[services."a.B"]\naction = "/x"\nfields = { x = "a.x" }\n', "carries the arguments as JSON"),
    ('[services."a.B"]\naction = "/x"\ntype = "p/T"\nsuccess = "ok"\n', "success and failure are for ROS services"),
    ('[services."a.B"]\naction = "/x"\ntype = "p/T"\ngoal = {}\n', "unknown key(s) ['goal']"),
])
def test_a_bad_route_is_named_with_its_value(tmp_path, text, message):
    with pytest.raises(InputFileError, match=r"ros.toml.*\[services\] a.B") as e:
        load_mapping(write(tmp_path, text))
    assert message in str(e.value)


def test_a_typed_route_serves_one_service_only(tmp_path):
    shared = load_mapping(write(tmp_path, '[services."a.B"]\naction = "/x"\ntype = "p/T"\n'
                                          '[services."a.C"]\naction = "/x"\ntype = "p/T"\n'))
    with pytest.raises(UntimelyError, match="a.B and a.C both map to /x"):
        shared.routes([("a", "B"), ("a", "C")])


def test_a_recorded_bag_holds_every_action_topic_and_the_json_topics(interface):
    from harness.sut.ros.recorder import recorded_topics
    typed = load_mapping(DEFAULT_MISSION_DIR / "ros-typed.toml")
    topics = recorded_topics(typed, [(s.module, s.name) for s in interface.services.values()])
    assert {"/move_base/goal", "/move_base/result", "/dala/ndd/feedback", "/dala/ndd/status", "/dala/ndd/cancel",
            "/dala/internal", "/dala/pong"} <= set(topics)
    assert not [t for t in topics if "init" in t]  # the Init ROS services: no topics to record


def test_ros2_exec_services_are_actions_the_others_services(interface):
    """ros2.toml: an action server per exec service, a ROS 2 service (untimely_msgs/srv/Call, its
    response's `code` the reply) per control and init service; the node to probe and drive."""
    mapping = load_mapping(DEFAULT_MISSION_DIR / "ros2.toml")
    kinds = {q: s.kind for q, s in interface.services.items()}
    routes = mapping.routes([(s.module, s.name) for s in interface.services.values()], kinds)
    assert {q: (r.kind, r.name) for q, r in routes.items() if q.startswith("ndd.")} == {
        "ndd.Init": ("service", "/dala/ndd/Init"), "ndd.SetParams": ("service", "/dala/ndd/SetParams"),
        "ndd.GotoPosition": ("action", "/dala/ndd/GotoPosition"), "ndd.Stop": ("action", "/dala/ndd/Stop")}
    assert {r.type for q, r in routes.items() if kinds[q] == "exec"} == {"untimely_msgs/Request"}
    assert {(r.type, r.code) for q, r in routes.items() if kinds[q] != "exec"} == {("untimely_msgs/Call", "code")}
    assert (mapping.node, mapping.lifecycle) == ("/dala", True)
    assert mapping.final_code("CANCELED", ("",), interface.replies) == "interrupted"

