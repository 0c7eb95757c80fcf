"""The injected defects, each shown by a short scenario on its variant and absent elsewhere."""
import pytest

from tests.support.sut_driver import Driver

VARIANTS = ("genom", "bip-a", "bip-b", "bare", "reference")


@pytest.mark.parametrize("variant", VARIANTS)
def test_genom_init_interrupts_the_running_activities_of_its_module(interface, variant):
    d = Driver(variant, interface)
    ready = d.prepare("aspect")
    reset = d.send(ready, "aspect.Reset")
    fuse = d.send(ready + 0.5, "aspect.Fuse")
    init = d.send(ready + 2, "aspect.Init")
    d.run(ready + 3)
    assert d.final(reset) == "ok" and d.final(init) == "ok"
    assert d.final(fuse) == ("interrupted" if variant == "genom" else None)


def stop_during_start_phase(interface, variant):
    d = Driver(variant, interface)
    ready = d.prepare("rflex", "sick")
    track = d.send(ready, "rflex.TrackSpeedStart")  # start phase: motor enable, 0.5 s
    stop = d.send(ready + 0.2, "rflex.Stop")
    later = d.send(ready + 1, "rflex.SetMode", mode="idle")
    other = d.send(ready + 1, "sick.OneShot")
    answers = d.ping(ready + 2)
    d.run(ready + 10)
    return d, track, stop, later, other, answers


def test_bip_a_deadlocks_when_stop_reaches_an_activity_in_its_start_phase(interface):
    d, track, stop, later, other, answers = stop_during_start_phase(interface, "bip-a")
    assert [d.final(r) for r in (track, stop, later)] == [None, None, None]  # rflex answers nothing more
    assert d.when(track, "intermediate") is None
    assert d.layer.modules["rflex"].deadlocked
    assert answers == []  # the liveness probe goes unanswered
    assert d.final(other) == "ok"  # the other modules still work


@pytest.mark.parametrize("variant", ("genom", "bip-b", "reference"))
def test_other_variants_interrupt_an_activity_in_its_start_phase(interface, variant):
    d, track, stop, later, _, answers = stop_during_start_phase(interface, variant)
    assert [d.final(r) for r in (track, stop, later)] == ["interrupted", "ok", "ok"]
    assert answers == [pytest.approx(1.0 + 2 + 0.001)]


def test_bip_a_interrupts_normally_after_the_start_phase(interface):
    d = Driver("bip-a", interface)
    ready = d.prepare("rflex")
    track = d.send(ready, "rflex.TrackSpeedStart")
    stop = d.send(ready + 1, "rflex.Stop")
    answers = d.ping(ready + 2)
    d.run(ready + 3)
    assert [d.final(track), d.final(stop)] == ["interrupted", "ok"] and answers


@pytest.mark.parametrize("variant,expected", [
    ("bip-a", "ok"), ("genom", "wait_init"), ("bip-b", "wait_init"), ("reference", "wait_init")])
def test_bip_a_pex_leaks_while_the_first_init_runs(interface, variant, expected):
    d = Driver(variant, interface)
    before = d.send(0.0, "aspect.Reset")
    d.send(0.1, "aspect.Init")  # runs until 0.601
    during = d.send(0.3, "aspect.Reset")
    after = d.send(1.0, "aspect.Reset")
    d.run(2.0)
    assert [d.final(r) for r in (before, during, after)] == ["wait_init", expected, "ok"]


def exclusion_during_start_phase(interface, variant, gap):
    d = Driver(variant, interface)
    ready = d.prepare()
    d.send(ready, "rflex.TrackSpeedStart")
    goto = d.send(ready + 1, "ndd.GotoPosition", x=9, y=4)  # start phase 0.2 s
    point = d.send(ready + 1 + gap, "antenna.Point", az=45)
    answers = d.ping(ready + 3)
    d.run(ready + 5)
    return d, goto, point, answers


def test_bip_b_deadlocks_when_an_exclusion_hits_an_activity_in_its_start_phase(interface):
    d, goto, point, answers = exclusion_during_start_phase(interface, "bip-b", gap=0.1)
    assert d.final(goto) is None and d.layer.modules["ndd"].deadlocked
    assert d.final(point) == "ok" and answers == []


@pytest.mark.parametrize("variant,gap", [("bip-b", 0.5), ("reference", 0.1), ("bip-a", 0.1)])
def test_the_same_exclusion_is_harmless_elsewhere_or_later(interface, variant, gap):
    d, goto, point, answers = exclusion_during_start_phase(interface, variant, gap)
    assert [d.final(goto), d.final(point)] == ["interrupted_excl", "ok"]
    assert answers and not any(m.deadlocked for m in d.layer.modules.values())
