import pytest

from harness import DEFAULT_MISSION_DIR
from harness.errors import InputFileError, ScriptError
from harness.target.script import load_script, parse, validate
from tests.support.arm_interface import arm_interface


def check(text, interface):
    validate(parse(text, "m.mission"), interface)


@pytest.mark.parametrize("text, message", [
    ("send rflex.Init as ri\nfly away\n", "m.mission:2: unknown step 'fly'"),
    ("sleep soon\n", "m.mission:1: sleep duration 'soon' is not a positive number"),
    ("sleep -1\n", "sleep duration '-1' is not a positive number"),
    ("send rflex.Init\nwait all timeout=0\n", "m.mission:2: timeout '0' is not a positive number"),
    ("wait all later\n", "unexpected 'later' after the handle"),
    ("send Init\n", "'send' needs MODULE.SERVICE first, got 'Init'"),
    ("send rflex.Init as\n", "'as' must end the line with one handle name"),
    ("send rflex.Init as all\n", "'as' must end the line"),
    ("send ndd.GotoPosition x=1 y\n", "argument 'y' is not of the form name=value"),
    ("# only a comment\n", "the script has no steps"),
    ("send rflex.Init\nsleep 1e308\n", "m.mission:2: sleep duration '1e308' is longer than a day (86400 s)"),
    ("send rflex.Init\nwait all timeout=1e308\n", "m.mission:2: timeout '1e308' is longer than a day (86400 s)"),
])
def test_parse_errors_name_line_and_value(text, message):
    with pytest.raises(ScriptError) as e:
        parse(text, "m.mission")
    assert message in str(e.value)


@pytest.mark.parametrize("text, message", [
    ("send wheels.Init\n", "m.mission:1: unknown service 'wheels.Init'; known modules: rflex, sick"),
    ("send rflex.Go\n", "unknown service 'rflex.Go'; module 'rflex' offers Init, SetMode, TrackSpeedStart, Stop"),
    ("send ndd.GotoPosition x=1 y=2 z=3\n", "ndd.GotoPosition has no argument 'z'; it takes x, y"),
    ("send ndd.GotoPosition x=1 x=2 y=2\n", "argument 'x' is given twice"),
    ("send rflex.Init as a\nwait b\n", "m.mission:2: wait on handle 'b', which no earlier line sends"),
    ("wait a\nsend rflex.Init as a\n", "m.mission:1: wait on handle 'a'"),
    ("send rflex.Init as a\nsend sick.Init as a\n", "m.mission:2: handle 'a' already names the request on line 1"),
])
def test_validation_errors_name_line_and_value(interface, text, message):
    with pytest.raises(ScriptError) as e:
        check(text, interface)
    assert message in str(e.value)


def test_out_of_domain_values_are_left_to_the_layer(interface):
    """Out of range, nan, infinite, of the wrong type, empty or missing: the layer must refuse them."""
    check("send ndd.GotoPosition x=-50 y=2\nsend rflex.SetMode mode=turbo\nsend ndd.GotoPosition x=far y=nan\n"
          "send ndd.GotoPosition x=inf\nsend rflex.SetMode mode=\"\"\n", interface)


def test_render_round_trips_and_keeps_comments(interface):
    script = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    again = parse(script.render(), "again")
    assert again.render() == script.render()
    assert [s.render() for s in again.steps] == [s.render() for s in script.steps]
    assert "sleep 3  # science photos" in script.render()


def test_golden_mission_uses_every_module_and_service_kind(interface):
    script = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    sent = [interface.services[s.service] for s in script.steps if s.op == "send"]
    assert {s.module for s in sent} == set(interface.modules)
    assert {s.kind for s in sent} == {"init", "control", "exec"}
    assert sum(s.service == "ndd.GotoPosition" for s in script.steps) == 3


def test_missing_script_file_is_named(interface, tmp_path):
    with pytest.raises(InputFileError, match="nope.mission: file not found; pass an existing mission script"):
        load_script(tmp_path / "nope.mission", interface)
    with pytest.raises(InputFileError, match=f"{tmp_path}: is a folder, not a file; pass the file itself"):
        load_script(tmp_path, interface)
    (tmp_path / "loop.mission").symlink_to(tmp_path / "loop.mission")
    with pytest.raises(InputFileError, match="loop.mission: is a symbolic link that loops; point it at a real file"):
        load_script(tmp_path / "loop.mission", interface)


def test_only_a_newline_ends_a_step_and_a_byte_order_mark_is_no_text(interface, tmp_path):
    path = tmp_path / "m.mission"
    path.write_bytes("\ufeffsend rflex.Init as ri  # a comment\u2028send sick.Init\fsend ndd.Init\r\nwait ri\n"
                     .encode())
    script = load_script(path, interface)
    assert [s.render() for s in script.steps] == [
        "send rflex.Init as ri  # a comment\u2028send sick.Init\fsend ndd.Init", "wait ri"]



@pytest.fixture
def arm(tmp_path):
    return arm_interface(tmp_path)


def test_a_cancel_renders_and_parses_back(arm):
    text = "send arm.move order=3 as g1\nsleep 0.5\ncancel g1 as c1  # halt it\ncancel g1\nwait c1\nwait g1\n"
    script = parse(text, "m.mission")
    validate(script, arm)
    assert script.render() == text
    cancel = script.steps[2]
    assert (cancel.op, cancel.cancelled, cancel.handle, cancel.comment) == ("cancel", "g1", "c1", "halt it")
    assert parse(script.render(), "again").steps == script.steps


@pytest.mark.parametrize("text, message", [
    ("cancel\n", "m.mission:1: 'cancel' takes the handle of one goal and an optional 'as HANDLE', got ''"),
    ("cancel g1 g2\n", "'cancel' takes the handle of one goal"),
    ("cancel all\n", "'cancel' takes the handle of one goal"),
    ("cancel g1 as\n", "'as' must end the line with one handle name"),
])
def test_a_malformed_cancel_is_refused_at_its_line(text, message):
    with pytest.raises(ScriptError) as e:
        parse(text, "m.mission")
    assert message in str(e.value)


@pytest.mark.parametrize("text, message", [
    ("cancel g1\nsend arm.move order=3 as g1\n", "m.mission:1: cancel of handle 'g1', which no earlier line sends"),
    ("send arm.move order=3 as g1\ncancel g2\n", "m.mission:2: cancel of handle 'g2', which no earlier line sends"),
    ("send arm.grip as g1\ncancel g1\n", "m.mission:2: cancel of handle 'g1', which names arm.grip, a control "
                                         "service (line 1); only the goal of an exec service"),
    ("send arm.move order=3 as g1\ncancel g1 as c\ncancel c\n", "m.mission:3: cancel of handle 'c', which names "
                                                                 "a cancel (line 2)"),
    ("send arm.home as h\ncancel h\n", "m.mission:2: cancel of arm.home needs the service arm.home_cancel, which the "
                                       "interface"),
    ("send arm.move order=3 as g1\ncancel g1 as g1\n", "m.mission:2: handle 'g1' already names the request on line 1"),
    ("send arm.move order=3 as g1\nwait c\ncancel g1 as c\n", "m.mission:2: wait on handle 'c'"),
])
def test_a_cancel_the_interface_cannot_run_is_refused_at_its_line(arm, text, message):
    with pytest.raises(ScriptError) as e:
        check(text, arm)
    assert message in str(e.value)


def test_the_missing_cancel_service_is_named_with_what_to_add(arm):
    with pytest.raises(ScriptError) as e:
        check("send arm.home as h\ncancel h\n", arm)
    assert 'add services.home_cancel = { kind = "control" } to its [modules.arm]' in str(e.value)
