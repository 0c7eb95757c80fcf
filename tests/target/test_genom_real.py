"""`untimely init --from-genom` on component descriptions as their authors wrote them (tests/genom/real/,
sources in tests/genom/SOURCES.md): what each states, checked by hand against the file, and a
10-mutant campaign on the stand-in adapter with at most 30% invalid mutants and no certain FN or FP."""
import pytest

from harness import store
from harness.cli import main
from harness.target.genom.reader import read_scopes
from harness.target.interface import load_interface, load_properties

from tests.support.paths import GENOM

pytestmark = pytest.mark.slow
INCLUDE = GENOM / "include"

# component -> (services in the interface, an AIB property and its dominators, as the .gen file says);
# REJECTIONS: the exceptions only validate codels throw (class R), the others are class T
EXPECTED = {
    # drone driver: connect/pconnect, the set_velocity/set_throttle functions and stop interrupt servo (305-...)
    "rotorcraft": (33, "servo", {"connect", "pconnect", "servo", "set_velocity", "set_throttle", "stop", "kill"}),
    # flight controller: servo is interrupted by itself and the functions that set a new reference
    "nhfc": (25, "servo", {"servo", "set_state", "set_position", "set_current_position", "stop", "kill"}),
    # planner: waypoint by take_off (152), goto (173), waypoint (197), replay (236), stop (263); not velocity (216)
    "maneuver": (21, "waypoint", {"take_off", "goto", "waypoint", "replay", "stop", "kill"}),
    # rover: 13 services and kill; Track is interrupted by JoystickOn (167), Track (192), Stop (203),
    # DirectTrack (224) and kill
    "rmp440": (14, "Track", {"JoystickOn", "Track", "Stop", "DirectTrack", "kill"}),
    # camera: no interrupts clause; kill interrupts connect
    "d435": (8, "connect", {"kill"}),
    "arucotag": (12, "add_marker", {"kill"}),
    # arm controller: servo by itself, set_state, set_position, set_current_position, set_velocity, stop
    "wamctrl": (29, "servo", {"servo", "set_state", "set_position", "set_current_position", "set_velocity",
                              "stop", "kill"}),
    # color tracking camera: 11 attributes, color_track, clear_findins and kill; color_track by itself (141)
    "ColorTracker": (14, "color_track", {"color_track", "kill"}),
}
# The preconditions (PC properties): only ColorTracker writes one, `after` at line 124 (four attributes,
# none of which is *the* init service: a PRE, no PEX); the seven others have no after or before clause.
PRECONDITIONS = {"ColorTracker": {"PRE(ColorTracker.color_track)": {"set_color", "set_distance_threshold",
                                                                  "set_camera_pose", "set_map_size"}}}

# rotorcraft: e_range only by set_battery_limits (line 173), an attribute whose one codel is its validate
# (line 171); wamctrl's e_inval comes from set_saturation_weights, whose validate has a codel beside it: T
REJECTIONS = {"rotorcraft": {"e_range"}}
# The VAL properties the validate codels state (service -> arguments, the rejection): only
# rotorcraft's set_battery_limits, whose one codel is `validate mk_set_battery_limits(in min, in max)`
# (line 171: unqualified names of its parameters battery.min = 14.0 and battery.max = 16.7, lines
# 166-167) and which throws e_range alone (line 173). Not the others, each for a reason init names:
# d435's four setters (lines 94-109) reject with e_io, which connect's codel also throws (line 79);
# arucotag's output_frame (135-136) with e_sys, also log's (153); arucotag's set_length (125),
# nhfc's five validates (105-150), rotorcraft's set_sensor_rate (153) and set_imu_calibration (221),
# wamctrl's set_mass (175) and set_emerg (253) throw nothing (WHY_NO_VAL: init names each line);
# maneuver, rmp440 and wamctrl's others validate services that have other codels, so which
# exception the validate throws is not written (init's note names each such exception).
NO_OWN, ALSO_ENDS = "the service throws no exception of its own", "also ends other services (class T"
WHY_NO_VAL = {"d435": {96: ALSO_ENDS, 100: ALSO_ENDS, 104: ALSO_ENDS, 108: ALSO_ENDS},
              "arucotag": {125: NO_OWN, 135: ALSO_ENDS},
              "nhfc": {105: NO_OWN, 110: NO_OWN, 135: NO_OWN, 144: NO_OWN, 149: NO_OWN},
              "rotorcraft": {153: NO_OWN, 221: NO_OWN}, "wamctrl": {175: NO_OWN, 253: NO_OWN}}
VALIDATED = {"rotorcraft": {"rotorcraft.set_battery_limits": ("e_range", {"min": "14.0", "max": "16.7"})}}
STANDARD_R = {"wait_init", "disallowed", "bad_params", "too_many_activities"}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_a_real_component_gives_its_clauses_and_a_campaign_that_runs(tmp_path, capsys, name):
    folder = tmp_path / name
    assert main(["init", str(folder), "--from-genom", str(GENOM / "real" / f"{name}.gen"), "-I", str(INCLUDE)]) == 0
    said = capsys.readouterr().out
    for line, why in WHY_NO_VAL.get(name, {}).items():
        assert any(f"{name}.gen:{line}: " in note and why in note for note in said.splitlines()), (line, why)
    interface = load_interface(folder / "interface.toml")
    properties = {p.id: p for p in load_properties(folder / "properties.toml", interface)}
    count, activity, dominators = EXPECTED[name]
    services = [s for s in interface.services if s.startswith(name + ".")]
    assert len(services) == count, services
    assert f"{name}.kill" in services and f"{name}.abort_activity" not in services
    aib = properties[f"AIB({name}.{activity})"]
    assert {y.split(".", 1)[1] for y in aib.y} == dominators
    assert {c for c, cls in interface.replies.items() if cls == "R"} - STANDARD_R == REJECTIONS.get(name, set())
    pcs = {p.id: {q.split(".", 1)[1] for q in p.q} for p in properties.values() if p.type == "PC"}
    assert pcs == PRECONDITIONS.get(name, {})
    vals = {p.x[0]: p.r_p for p in properties.values() if p.type == "VAL"}
    assert vals == {x: reply for x, (reply, _) in VALIDATED.get(name, {}).items()}
    golden = (folder / "golden.mission").read_text()
    for x, (_, args) in VALIDATED.get(name, {}).items():
        assert set(interface.services[x].args) == set(args)
        assert " ".join([f"send {x}", *(f"{a}={v}" for a, v in args.items())]) + "\n" in golden, "their defaults"
    text = (folder / "properties.toml").read_text()
    assert f"{name}.gen:" in text or "genom3's standard service kill" in text, "each property cites its clause"
    db = tmp_path / "c.duckdb"
    assert main(["campaign", "--mission", str(folder), "--sut", "adapter", "--mutants", "10", "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    invalid = con.execute("select count(*) filter (not valid), count(*) from scripts where kind = 'mutant'").fetchone()
    # a suspicious FN (an ok and a request closer than the interface latency) is the bench's own doubt
    bad = con.execute("select count(*) from verdicts where verdict in ('FN', 'FP') and certain").fetchone()[0]
    outcomes = dict(con.execute("select outcome, count(*) from traces group by all").fetchall())
    con.close()
    assert invalid[1] == 10 and invalid[0] <= 3, invalid
    assert bad == 0, "the stand-in does what the description says: no FN, no FP"
    assert set(outcomes) == {"completed"}, outcomes


def test_the_standard_interface_restates_genom3s_own_template(tmp_path):
    """harness/target/genom/standard.gen restates templates/common/genom.gen of the GenoM3 sources
    (tests/genom/real/genom3/genom.gen, unchanged, included here with -I as a component would):
    the same standard services with the same clauses, and only exceptions the template declares."""
    gen = tmp_path / "c.gen"
    gen.write_text('#include "genom.gen"\ncomponent c { activity A(); };\n')
    _, interfaces, _ = read_scopes(gen, [GENOM / "real" / "genom3"])
    ours, theirs = (next(s for s in interfaces if s.name == "genom" and s.where.file.endswith(end))
                    for end in ("standard.gen", "genom3/genom.gen"))
    assert {n: (s.kind, s.clauses) for n, s in ours.services.items()} == \
        {n: (s.kind, s.clauses) for n, s in theirs.services.items()}
    assert set(ours.exceptions) <= set(theirs.exceptions) and "interrupted" in ours.exceptions
    assert main(["init", str(tmp_path / "t"), "--from-genom", str(gen), "-I", str(GENOM / "real" / "genom3")]) == 0
    interface = load_interface(tmp_path / "t" / "interface.toml")
    properties = load_properties(tmp_path / "t" / "properties.toml", interface)
    assert [p.y for p in properties if p.id == "AIB(c.A)"] == [("c.kill",)], "kill of the template: interrupt all"
