"""Each protection (PEX, AIB, PRE, EXC) on the variants that have it, and its absence elsewhere;
argument checks, activity slots, check order, control-task order."""
import json

import pytest

from tests.support.sut_driver import Driver

VARIANTS = ("genom", "bip-a", "bip-b", "bare", "reference")


def expect(table):
    return pytest.mark.parametrize("variant,expected", list(table.items()), ids=list(table))


@expect({"genom": "wait_init", "bip-a": "wait_init", "bip-b": "wait_init", "reference": "wait_init", "bare": "ok"})
def test_pex_exec_before_init(interface, variant, expected):
    d = Driver(variant, interface)
    shot = d.send(0.0, "sick.OneShot")
    d.run(2.0)
    assert d.final(shot) == expected


@pytest.mark.parametrize("variant", VARIANTS)
def test_pex_exec_after_init_is_accepted(interface, variant):
    d = Driver(variant, interface)
    ready = d.prepare("sick")
    shot = d.send(ready, "sick.OneShot")
    d.run(ready + 1)
    assert d.final(shot) == "ok"
    assert d.when(shot, "intermediate") == pytest.approx(ready + 0.001 + 0.1)  # after the start phase


@expect({"genom": "interrupted", "bip-a": "interrupted", "bip-b": "interrupted", "reference": "interrupted",
         "bare": None})
def test_aib_same_type_request_interrupts_the_running_one(interface, variant, expected):
    d = Driver(variant, interface)
    ready = d.prepare("rflex")
    first = d.send(ready, "rflex.TrackSpeedStart")
    second = d.send(ready + 2, "rflex.TrackSpeedStart")
    d.run(ready + 5)
    assert d.final(first) == expected  # bare: both keep running side by side
    assert d.final(second) is None and d.when(second, "intermediate") is not None
    assert len(d.layer.modules["rflex"].running("TrackSpeedStart")) == (2 if variant == "bare" else 1)


@expect({"genom": "interrupted", "bip-a": "interrupted", "bip-b": "interrupted", "reference": "interrupted",
         "bare": "ok"})
def test_aib_stop_ends_the_module_activities(interface, variant, expected):
    d = Driver(variant, interface)
    ready = d.prepare("sick")
    laser = d.send(ready, "sick.ContinuousShot")
    stop = d.send(ready + 2, "sick.Stop")
    d.run(ready + 3)
    assert d.final(laser) == expected  # bare: stopped, but it says ok
    assert d.final(stop) == "ok" and d.when(stop) > d.when(laser)
    assert d.layer.modules["sick"].running() == []


@pytest.mark.parametrize("variant", ("genom", "bip-a", "bip-b", "reference"))  # bare checks no range
def test_aib_a_rejected_dominating_request_interrupts_nothing(interface, variant):
    d = Driver(variant, interface)
    ready = d.prepare("rflex", "ndd")
    goto = d.send(ready, "ndd.GotoPosition", x=9, y=4)
    wrong = d.send(ready + 1, "ndd.GotoPosition", x=99, y=4)
    d.run(ready + 2)
    assert d.final(wrong) == "bad_params"
    assert d.final(goto) is None and d.layer.modules["ndd"].running("GotoPosition")


@expect({"genom": "ok", "bip-a": "ok", "bare": "ok", "bip-b": "disallowed", "reference": "disallowed"})
def test_pre_exec_without_its_required_services(interface, variant, expected):
    d = Driver(variant, interface)
    ready = d.prepare("sick", configure=False)  # no sick.SetParams
    shot = d.send(ready, "sick.OneShot")
    d.run(ready + 1)
    assert d.final(shot) == expected


@pytest.mark.parametrize("variant", ("bip-b", "reference"))
def test_pre_needs_every_required_service_to_have_ended_ok(interface, variant):
    d = Driver(variant, interface)
    ready = d.prepare("antenna")  # SetChannel done, Point not yet
    early = d.send(ready, "antenna.Communication", duration=2)
    point = d.send(ready + 0.1, "antenna.Point", az=90)
    during = d.send(ready + 0.5, "antenna.Communication", duration=2)  # Point still slewing
    after = d.send(ready + 5, "antenna.Communication", duration=2)
    d.run(ready + 8)
    assert [d.final(r) for r in (early, point, during, after)] == ["disallowed", "ok", "disallowed", "ok"]


@expect({"genom": None, "bare": None, "bip-a": "interrupted_excl", "bip-b": "interrupted_excl",
         "reference": "interrupted_excl"})
def test_exc_a_later_point_interrupts_navigation(interface, variant, expected):
    d = Driver(variant, interface)
    ready = d.prepare()
    d.send(ready, "rflex.TrackSpeedStart")
    goto = d.send(ready, "ndd.GotoPosition", x=9, y=4)
    point = d.send(ready + 2, "antenna.Point", az=90)
    d.run(ready + 5)
    assert d.final(goto) == expected
    assert d.final(point) == "ok"


@expect({"genom": None, "bare": None, "bip-a": "interrupted_excl", "bip-b": "interrupted_excl",
         "reference": "interrupted_excl"})
def test_exc_a_later_navigation_interrupts_point_and_reset(interface, variant, expected):
    d = Driver(variant, interface)
    ready = d.prepare()
    point = d.send(ready, "antenna.Point", az=180)  # slews 4 s
    goto = d.send(ready + 1, "ndd.GotoPosition", x=9, y=4)
    reset = d.send(ready + 2, "aspect.Reset")
    d.run(ready + 2.15)
    assert d.final(point) == expected
    assert d.final(reset) is None  # Reset, in its start phase, excludes the navigation at once
    assert d.final(goto) == expected


RANGE_CHECKED = {"genom", "bip-a", "bip-b", "reference"}  # layer.toml: RANGE or VAL; bare checks nothing


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("service,args,broken,rejected_by", [
    ("ndd.GotoPosition", {"x": 21, "y": 4}, "x", RANGE_CHECKED),
    ("ndd.GotoPosition", {"x": "-inf", "y": 4}, "x", RANGE_CHECKED),
    ("sick.SetParams", {"fov": 10, "range": 8}, "fov", RANGE_CHECKED),
    ("ndd.GotoPosition", {"x": "nan", "y": 4}, "x", {"reference"}),  # `x < min || x > max` lets nan pass
    ("ndd.GotoPosition", {"x": "east", "y": 4}, "x", {"reference"}),
    ("ndd.GotoPosition", {"x": 3}, "y", {"reference"}),
    ("rflex.SetMode", {"mode": "turbo"}, "mode", {"reference"}),
])
def test_bad_params_as_the_variants_argument_checks_say(interface, variant, service, args, broken, rejected_by):
    """A value the variant checks is rejected; one it does not is let through, noted as ground truth."""
    d = Driver(variant, interface)
    ready = d.prepare()
    request = d.send(ready, service, **args)
    d.run(ready + 1)
    noted = [json.loads(e[2]) for e in d.layer.world_events if e[1] == "unchecked_value"]
    if variant in rejected_by:
        assert d.final(request) == "bad_params" and noted == []
    else:
        assert d.final(request) != "bad_params"
        assert [(n["rqst_id"], n["service"], n["argument"]) for n in noted] == [(request, service, broken)]


def test_too_many_activities_on_bare(interface):
    d = Driver("bare", interface)
    ready = d.prepare("rflex")
    tracks = [d.send(ready + n * 0.1, "rflex.TrackSpeedStart") for n in range(4)]
    d.run(ready + 2)
    assert [d.final(t) for t in tracks] == [None, None, None, "too_many_activities"]


def test_checks_come_in_order_bad_params_pex_pre_slots(interface):
    d = Driver("reference", interface)
    bad_before_init = d.send(0.0, "ndd.GotoPosition", x=-1, y=0)
    unprepared_before_init = d.send(0.0, "ndd.GotoPosition", x=1, y=1)
    d.send(0.0, "ndd.Init")
    unconfigured = d.send(1.0, "ndd.GotoPosition", x=1, y=1)
    d.run(2.0)
    assert [d.final(r) for r in (bad_before_init, unprepared_before_init, unconfigured)] == [
        "bad_params", "wait_init", "disallowed"]


def test_control_task_serves_requests_in_order_one_latency_apart(interface):
    d = Driver("reference", interface)
    requests = [d.send(0.0, "sick.SetParams", fov=90 + n, range=5) for n in range(3)]
    init = d.send(0.0, "sick.Init")
    d.run(1.0)
    assert [d.when(r) for r in requests] == pytest.approx([0.001, 0.002, 0.003])
    assert [d.when(r, "request") for r in requests] == [d.when(r) for r in requests]  # taken, then served
    assert d.when(init, "request") == pytest.approx(0.004)
    assert d.when(init) == pytest.approx(0.004 + 0.5)
    assert d.layer.modules["sick"].settings["fov"] == 92.0
    assert [kind for _, r, kind, _ in d.replies if r in requests] == ["request", "final"] * 3  # no intermediate
