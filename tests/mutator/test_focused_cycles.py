"""The focused strategy's context (harness/mutator/focused.py, Builder.closure) on init services
that need each other: a module's inits need one another (a cycle every module with two inits
has), sent in the golden's order; PC properties that make services need each other in a cycle
are refused, naming the cycle, the properties and their file. Before, both recursed forever."""
import pytest

from harness.errors import UntimelyError
from harness.mutator.focused import Plan
from harness.mutator.timeline import ScriptTimeline
from harness.target.interface import load_interface, load_properties
from harness.target.script import parse
from harness.trace import Trace

INTERFACE = """
[replies]
ok = "T"
not_ready = "R"

[modules.arm]
services.Init = { kind = "init" }
services.Calibrate = { kind = "init" }
services.Move = { kind = "exec", args = { x = { type = "float", min = 0.0, max = 1.0 } } }
"""
GOLDEN = """send arm.Calibrate as c
wait c timeout=5
send arm.Init as i
wait i timeout=5
send arm.Move x=0.5 as m
wait m timeout=5
"""
MOVE = """
[[property]]
id = "READY(arm.Move)"
family = "READY"
type = "PC"
x = ["arm.Move"]
q = ["arm.Init"]
r_p = "not_ready"
"""
CYCLE = MOVE + """
[[property]]
id = "ORDER(arm.Init)"
family = "ORDER"
type = "PC"
x = ["arm.Init"]
q = ["arm.Calibrate"]
r_p = "not_ready"

[[property]]
id = "ORDER(arm.Calibrate)"
family = "ORDER"
type = "PC"
x = ["arm.Calibrate"]
q = ["arm.Init"]
r_p = "not_ready"
"""


def plan(tmp_path, properties: str) -> Plan:
    (tmp_path / "interface.toml").write_text(INTERFACE)
    (tmp_path / "properties.toml").write_text(properties)
    interface = load_interface(tmp_path / "interface.toml")
    golden = parse(GOLDEN, "golden.mission")
    timeline = ScriptTimeline(golden, Trace("sim", 0, events=[]), interface.replies)
    return Plan(golden, timeline, interface, load_properties(tmp_path / "properties.toml", interface), 1,
                str(tmp_path / "properties.toml"))



def test_a_modules_inits_that_need_each_other_are_sent_in_the_goldens_order(tmp_path):
    built = plan(tmp_path, MOVE)
    assert built.builder.closure(["arm.Move"]) in (["arm.Calibrate", "arm.Init"], ["arm.Init", "arm.Calibrate"])
    for n in range(len(built.aims)):
        test = built.test(n, f"test {n}")
        assert test.valid, test.invalid_reason
        sends = [s.service for s in test.script.steps if s.op == "send"]
        if "arm.Calibrate" in sends and "arm.Init" in sends:
            assert sends.index("arm.Calibrate") < sends.index("arm.Init"), test.body  # the golden's order
    without = built.builder.closure(["arm.Move"], without="arm.Init")
    assert without == [], "a test of Move without Init leaves out what needs Init too"


def test_pc_properties_that_need_each_other_in_a_cycle_are_refused_naming_it(tmp_path):
    with pytest.raises(UntimelyError) as refused:  # when the plan is made, before any test runs
        plan(tmp_path, CYCLE)
    said = str(refused.value)
    for words in (str(tmp_path / "properties.toml"), "need each other in a cycle",
                  "ORDER(arm.Init) makes arm.Init need arm.Calibrate ok before it",
                  "ORDER(arm.Calibrate) makes arm.Calibrate need arm.Init ok before it", "remove the Q of one"):
        assert words in said, said
    assert "arm.Init -> arm.Calibrate -> arm.Init" in said or "arm.Calibrate -> arm.Init -> arm.Calibrate" in said
