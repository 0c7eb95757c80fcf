"""The golden mission through the executive on every variant: it completes without damage.

(Speed is measured by bench/golden_bench.py, not here.)"""
import pytest

from harness import DEFAULT_MISSION_DIR
from harness.sut.executive import run_script
from harness.target.script import load_script
from tests.support.sut_driver import WORLD

LONG_RUNNING = {("rflex", "TrackSpeedStart"), ("sick", "ContinuousShot"), ("aspect", "Fuse")}


@pytest.mark.parametrize("variant", ("reference", "genom", "bip-a", "bip-b", "bare"))
def test_golden_mission_completes_without_damage(interface, variant):
    script = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    trace = run_script(script, variant, 3, interface, WORLD)
    assert (trace.outcome, trace.error) == ("completed", None)
    assert trace.world_events == []  # no collision, no antenna or map mishap
    finals = {(module, service): reply for _, _, kind, _, module, service, _, reply in trace.internal_events
              if kind == "final"}
    stopped = "ok" if variant == "bare" else "interrupted"
    assert {k for k, reply in finals.items() if reply != "ok"} == (set() if variant == "bare" else LONG_RUNNING)
    assert all(finals[k] == stopped for k in LONG_RUNNING)
    answered = sorted(e[3] for e in trace.internal_events if e[2] == "final")
    assert answered == sorted(e[3] for e in trace.internal_events if e[2] == "request")  # one final each
    assert 60 < trace.sim_s < 120
