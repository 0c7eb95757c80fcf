"""`untimely init DIR [--from-genom FILE.gen]`: a target folder whose golden run completes against
its own adapter and whose campaign runs (keeping the adapter between runs); what three GenoM3
descriptions (tests/genom/, written in the style of public components) state, as interface and
properties; the refusals."""
from pathlib import Path

import pytest

from harness import store
from harness.cli import main
from harness.target.interface import load_interface, load_properties
from harness.target.mission import load_mission

GENOM = Path(__file__).parent / "genom"


def test_the_example_target_runs_its_golden_mission_and_a_campaign(tmp_path, capsys):
    folder = tmp_path / "robot"
    assert main(["init", str(folder)]) == 0
    assert "next: untimely run" in capsys.readouterr().out
    mission = load_mission(folder)
    assert set(mission.interface.modules) == {"base", "camera"}
    assert [p.id for p in mission.properties()] == ["PEX(base)", "PEX(camera)", "AIB(base.Move)",
                                                    "AIB(camera.Capture)", "PRE(base.Move)"]
    db = tmp_path / "c.duckdb"
    assert main(["run", str(folder / "golden.mission"), "--sut", "adapter", "--db", str(db)]) == 0
    assert "outcome    completed" in capsys.readouterr().out
    assert main(["campaign", "--mission", str(folder), "--sut", "adapter", "--mutants", "6", "--db",
                 str(tmp_path / "campaign.duckdb")]) == 0
    con = store.connect(tmp_path / "campaign.duckdb", read_only=True)
    outcomes = con.execute("select outcome, count(*) from traces group by all").fetchall()
    judged = con.execute("select count(*) from verdicts").fetchone()[0]
    later_runs = con.execute("select count(*) from trace_runs where not ends_with(sut_info, 'run 1')").fetchone()[0]
    con.close()
    assert dict(outcomes).get("completed", 0) >= 2 and judged > 0, outcomes
    assert later_runs > 0, "the stand-in adapter offers reuse: a campaign of 7 runs keeps it for later runs"


def _derived(tmp_path, name):
    folder = tmp_path / name
    assert main(["init", str(folder), "--from-genom", str(GENOM / f"{name}.gen")]) == 0
    interface = load_interface(folder / "interface.toml")
    properties = {p.id: p for p in load_properties(folder / "properties.toml", interface)}
    kinds = {s: interface.services[s].kind for s in interface.services}
    return folder, interface, kinds, properties


def test_a_mobile_base_with_interrupt_clauses(tmp_path, capsys):
    folder, interface, kinds, properties = _derived(tmp_path, "wheelbase")
    assert kinds == {"wheelbase.Init": "init", "wheelbase.SetSpeedLimits": "control",
                     "wheelbase.GetSpeedLimits": "control", "wheelbase.Track": "exec", "wheelbase.Goto": "exec",
                     "wheelbase.Stop": "control"}
    assert {c: interface.replies[c] for c in ("e_sys", "e_bad_device", "e_emergency", "interrupted")} == {
        "e_sys": "T", "e_bad_device": "T", "e_emergency": "T", "interrupted": "Z"}
    assert list(properties) == ["PEX(wheelbase)", "PRE(wheelbase.Track)", "AIB(wheelbase.Track)",
                                "AIB(wheelbase.Goto)"]
    assert properties["PEX(wheelbase)"].x == ("wheelbase.Track", "wheelbase.Goto")
    assert properties["PEX(wheelbase)"].q == ("wheelbase.Init",)
    assert properties["PRE(wheelbase.Track)"].q == ("wheelbase.SetSpeedLimits",), "after Init is PEX's"
    # `interrupt` and `interrupts` alike; Stop, a function, interrupts both activities
    assert properties["AIB(wheelbase.Goto)"].y == ("wheelbase.Track", "wheelbase.Goto", "wheelbase.Stop")
    assert properties["AIB(wheelbase.Track)"].type == "EE" and properties["AIB(wheelbase.Track)"].z_p == "interrupted"
    assert "service inputs" in capsys.readouterr().out
    assert main(["run", str(folder / "golden.mission"), "--sut", "adapter", "--db", str(tmp_path / "w.duckdb")]) == 0


def test_a_planner_whose_stop_interrupts_all(tmp_path, capsys):
    _, interface, kinds, properties = _derived(tmp_path, "maneuver2")
    assert kinds["maneuver2.set_bounds"] == "control" and kinds["maneuver2.stop"] == "control"
    assert kinds["maneuver2.goto"] == "exec"
    assert not any(k == "init" for k in kinds.values())
    assert "no init service" in capsys.readouterr().out
    assert properties["PRE(maneuver2.goto)"].q == ("maneuver2.set_current_state", "maneuver2.set_bounds")
    assert properties["PRE(maneuver2.waypoint)"].q == ("maneuver2.goto",)
    # `interrupts all` makes stop a dominator of every activity, even one without clauses
    assert properties["AIB(maneuver2.set_current_state)"].y == ("maneuver2.stop",)
    assert properties["AIB(maneuver2.waypoint)"].y == ("maneuver2.take_off", "maneuver2.goto", "maneuver2.stop")
    assert not any(p.startswith("PEX") for p in properties)
    assert interface.replies["e_limits"] == "T"


def test_a_motor_controller_with_an_init_function_and_unknown_names(tmp_path, capsys):
    _, interface, kinds, properties = _derived(tmp_path, "quadmotors")
    assert kinds == {"quadmotors.init": "init", "quadmotors.start": "exec", "quadmotors.servo": "exec",
                     "quadmotors.stop": "exec", "quadmotors.set_velocity": "control"}
    assert list(properties) == ["PEX(quadmotors)", "PRE(quadmotors.servo)", "AIB(quadmotors.start)",
                                "AIB(quadmotors.servo)"]
    assert properties["PEX(quadmotors)"].x == ("quadmotors.start", "quadmotors.servo", "quadmotors.stop")
    assert properties["AIB(quadmotors.servo)"].y == ("quadmotors.servo", "quadmotors.stop")
    assert "e_started" in interface.replies, "an exception declared after one with members"
    out = capsys.readouterr().out
    assert "quadmotors.servo (line 30) interrupts 'spin_down', which the component does not declare" in out
    assert "quadmotors.stop (line 39) interrupts 'spin'" in out


def test_an_existing_target_is_never_overwritten(tmp_path, capsys):
    assert main(["init", str(tmp_path)]) == 0
    before = (tmp_path / "golden.mission").read_text()
    assert main(["init", str(tmp_path)]) == 2
    assert "already holds interface.toml, properties.toml, golden.mission, suts.toml, adapter.py" in \
        capsys.readouterr().err
    assert (tmp_path / "golden.mission").read_text() == before


@pytest.mark.parametrize("text, message", [
    (None, "no such file; give a GenoM3 .gen file"),
    ("/* nothing */ struct s { long a; };", "no `component NAME { ... };` found"),
    ("component c { version \"1\";", "component c has no closing brace"),
    ("component c { version \"1\"; };", "component c: declares no attribute, function or activity"),
])
def test_a_gen_file_that_cannot_be_read_is_refused_naming_it(tmp_path, capsys, text, message):
    gen = tmp_path / "bad.gen"
    if text is not None:
        gen.write_text(text)
    assert main(["init", str(tmp_path / "t"), "--from-genom", str(gen)]) == 2
    err = capsys.readouterr().err
    assert message in err and (text is None or str(gen) in err)
    assert not (tmp_path / "t").exists()
