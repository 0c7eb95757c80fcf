"""What the modules do in the world: navigation with and without the map, the antenna's link,
the laser and the map posters, the layer's own errors and reprs."""
import math

import pytest

from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.sut.simulated.kernel import Environment
from harness.sut.simulated.layer import FunctionalLayer
from tests.support.sut_driver import WORLD, Driver


def drive(interface, variant="reference", goal=(9, 4), fuse=True, at=None):
    """Wheels, laser and (optionally) the map running, then GotoPosition to `goal`."""
    d = Driver(variant, interface)
    ready = d.prepare()
    reset = d.send(ready, "aspect.Reset")
    d.send(ready + 0.3, "rflex.TrackSpeedStart")
    d.send(ready + 0.3, "sick.ContinuousShot")
    if fuse:
        d.send(ready + 0.3, "aspect.Fuse")
    goto = d.send(at or ready + 1.5, "ndd.GotoPosition", x=goal[0], y=goal[1])
    return d, reset, goto


def test_ndd_reaches_the_goal_around_the_rock_it_has_mapped(interface):
    d, _, goto = drive(interface)
    d.run(40)
    x, y, _ = d.world.pose
    assert d.final(goto) == "ok" and math.dist((x, y), (9, 4)) <= 0.25
    assert "collision" not in d.world_kinds()
    assert d.posters.ref == (0.0, 0.0) and d.world.still  # ends by writing Ref = 0
    rock = d.world.spec.rocks[0]  # on the straight line from (2, 2) to (9, 4)
    assert d.posters.cart_a.clearance(rock.x + rock.radius, rock.y) < 0.2  # it was mapped


def test_navigating_without_the_map_hits_the_rock(interface):
    d, _, goto = drive(interface, fuse=False)
    d.run(40)
    assert d.world_kinds()[:2] == ["navigation_without_map", "collision"]
    assert '"with": "rock 1"' in d.layer.world_events[1][2]
    assert d.final(goto) == "goal_unreachable"  # blocked by the rock: no progress for 5 s
    x, y, _ = d.world.pose
    assert math.dist((x, y), (5.5, 3.0)) >= 0.6 + 0.4 - 0.05  # the rock stopped the rover


def test_a_goal_inside_a_mapped_rock_is_unreachable(interface):
    d, _, goto = drive(interface, goal=(5.5, 3.0))
    d.run(6)
    assert d.final(goto) == "goal_unreachable" and d.when(goto) < 4
    assert "collision" not in d.world_kinds()


def test_no_progress_when_the_wheels_do_not_track(interface):
    d = Driver("reference", interface)
    ready = d.prepare()
    goto = d.send(ready, "ndd.GotoPosition", x=9, y=4)  # no TrackSpeedStart
    d.run(ready + 8)
    assert d.final(goto) == "goal_unreachable"
    assert 5 < d.when(goto) - ready < 6 and d.world.odometer == 0


def test_rflex_in_idle_mode_does_not_move(interface):
    d = Driver("bip-a", interface)  # no PRE: TrackSpeedStart runs without SetMode
    ready = d.prepare("rflex", "ndd", configure=False)
    d.send(ready, "rflex.TrackSpeedStart")
    goto = d.send(ready, "ndd.GotoPosition", x=9, y=4)
    d.run(ready + 8)
    assert d.final(goto) == "goal_unreachable" and d.world.odometer == 0


def test_a_scan_fills_scart_and_reset_clears_the_map(interface):
    d = Driver("reference", interface)
    ready = d.prepare()
    shot = d.send(ready, "sick.OneShot")
    d.send(ready + 0.5, "aspect.Reset")  # required before Fuse
    fuse = d.send(ready + 0.8, "aspect.Fuse")
    d.run(ready + 1.5)
    scan = d.posters.scart
    assert d.final(shot) == "ok" and scan.seq == 1 and scan.pose == d.world.pose
    assert scan.hits[0] == (pytest.approx(-math.pi / 2), pytest.approx(2.0))  # the bound y = 0, 2 m right
    assert all(round(math.degrees(b)) % 10 == 0 and 0 < dist <= 8 for b, dist in scan.hits)  # one ray / 10 deg
    assert d.posters.cart_a.occupied
    reset = d.send(ready + 2, "aspect.Reset")  # also interrupts Fuse
    d.run(ready + 3)
    assert d.final(reset) == "ok" and d.final(fuse) == "interrupted"
    assert not d.posters.cart_a.occupied


def talk_while_driving(interface, start_driving):
    d = Driver("genom", interface)  # no EXC: nothing keeps navigation and the antenna apart
    ready = d.prepare()
    d.send(ready, "rflex.TrackSpeedStart")
    point = d.send(ready, "antenna.Point", az=90)  # 2 s of slewing
    talk = d.send(ready + 3, "antenna.Communication", duration=10)
    d.send(start_driving, "ndd.GotoPosition", x=4, y=2)
    d.run(ready + 15)
    return d, point, talk


def test_communication_ends_link_lost_when_the_rover_moves(interface):
    d, point, talk = talk_while_driving(interface, start_driving=6)
    assert [d.final(point), d.final(talk)] == ["ok", "link_lost"]
    assert 6.2 < d.when(talk) < 7
    assert d.world_kinds() == ["navigation_without_map", "link_broken_while_moving"]


def test_pointing_while_driving_is_noted_and_loses_the_orbiter(interface):
    d, point, talk = talk_while_driving(interface, start_driving=1.5)
    assert [d.final(point), d.final(talk)] == ["ok", "link_lost"]
    assert d.world_kinds() == ["navigation_without_map", "drove_with_antenna_deployed"]


def test_communication_without_pointing_finds_no_orbiter(interface):
    d = Driver("bare", interface)
    ready = d.prepare("antenna")
    talk = d.send(ready, "antenna.Communication", duration=5)
    d.run(ready + 1)
    assert d.final(talk) == "link_lost" and d.when(talk) < ready + 0.5


def test_ping_is_answered_within_one_control_latency(interface):
    d = Driver("reference", interface)
    answers = d.ping(3.0)
    d.run(4.0)
    assert answers == [pytest.approx(3.001)]


def test_unknown_variant_names_the_known_ones(interface):
    with pytest.raises(UntimelyError, match=r"unknown variant 'bip-c'; choose one of genom, bip-a, bip-b, "
                                            r"bare, reference"):
        FunctionalLayer(Environment(), "bip-c", interface, WORLD)


def test_an_interface_service_the_layer_lacks_is_refused(tmp_path, interface):
    text = (WORLD.parent / "interface.toml").read_text().replace(
        'services.Stop = { kind = "exec" }\n\n[modules.sick]',
        'services.Stop = { kind = "exec" }\nservices.Jump = { kind = "exec" }\n\n[modules.sick]')
    path = tmp_path / "interface.toml"
    path.write_text(text)
    with pytest.raises(UntimelyError, match=r"declares rflex\.Jump \(exec\), which the simulated layer "
                                            r"does not implement"):
        FunctionalLayer(Environment(), "reference", load_interface(path), WORLD)


def test_a_request_for_an_undeclared_service_is_refused(interface):
    layer = FunctionalLayer(Environment(), "reference", interface, WORLD)
    with pytest.raises(UntimelyError, match=r"request 4 names 'rflex\.Fly', which the interface .* does not declare"):
        layer.receive(4, "rflex.Fly", {}, lambda *a: None)


def test_reprs_show_variant_modules_and_activities(interface):
    d = Driver("reference", interface)
    ready = d.prepare("rflex")
    d.send(ready, "rflex.TrackSpeedStart")
    d.run(ready + 0.2)
    rflex = d.layer.modules["rflex"]
    assert repr(rflex) == "<Module rflex initialised [TrackSpeedStart#3 starting]>"
    assert repr(rflex.activities[0]) == "<Activity rflex.TrackSpeedStart #3 starting>"
    assert repr(d.layer).startswith("<FunctionalLayer reference t=1.200 <Module rflex initialised")
    assert "<Module sick uninitialised []>" in repr(d.layer)
    assert repr(d.layer.variant) == "<Variant reference protections=VAL,PEX,AIB,PRE,EXC defects=->"
