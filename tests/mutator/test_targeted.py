"""Targeted generation: what falsifies each property type, the golden timeline, reproducibility,
genericity (a made-up mission), the coverage target on reference, and the campaign's --strategy."""
import json

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.store.record import record_of
from harness.campaign.config import campaign_config, find_campaign
from harness.campaign.request import CampaignRequest
from harness.cli import main
from harness.errors import StoreError, UntimelyError
from harness.sut.executive import run_script
from harness.target.interface import Property, load_interface, load_properties
from harness.analysis.judge import Judge
from harness.mutator import targeted
from harness.mutator.operators import Draw
from harness.mutator.targeted import GoldenRun
from harness.target.mission import load_mission
from harness.target.script import load_script, parse
from harness.mutator.timeline import ScriptTimeline
from harness.trace import Trace


def aimed(count: int, seed: int) -> Draw:
    return Draw(count, seed, targeted.SITES_PER_MUTANT)


def test_each_type_is_falsified_the_way_its_condition_says():
    pc = Property("P", "F", "PC", x=("m.X",), q=("m.Q",), r_p="no")
    assert targeted.falsifiers(pc) == [targeted.Falsifier("before_ok", send=("m.X",), need=("m.Q",))]
    ee = Property("E", "F", "EE", x=("m.X",), y=("m.Y", "m.Z"), z_p="int")
    assert targeted.falsifiers(ee) == [targeted.Falsifier("during", send=("m.Y", "m.Z"), running=("m.X",))]
    es = Property("S", "F", "ES", x=("m.X",), y=("m.Y",), r_p="no")
    assert targeted.falsifiers(es) == [targeted.Falsifier("during", send=("m.X",), running=("m.Y",))]
    mx = Property("M", "F", "MX_I", x=("a.X",), y=("b.Y",), z_p="int")
    assert {(f.send, f.running) for f in targeted.falsifiers(mx)} == {(("b.Y",), ("a.X",)), (("a.X",), ("b.Y",))}
    ex = Property("X", "F", "EX", x=("m.X",), y=("m.Y",), r_p="no", z_p="int")
    assert len(targeted.falsifiers(ex)) == 2


def test_disturbers_are_the_module_services_that_do_not_dominate(interface, properties):
    aib = next(p for p in properties if p.id == "AIB(antenna.Point)")
    assert targeted.disturbers(aib, interface) == [targeted.Falsifier(
        "during", send=("antenna.Init", "antenna.SetChannel", "antenna.Communication"),
        running=("antenna.Point",), disturb=True)]
    assert targeted.disturbers(next(p for p in properties if p.type == "PC"), interface) == []


@pytest.fixture(scope="module")
def golden_run(interface, properties):
    golden = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    trace = run_script(golden, "reference", 7, interface, DEFAULT_MISSION_DIR / "world.toml")
    return golden, trace, Judge(interface, properties).verdicts([trace])[0]


def test_the_timeline_says_what_runs_and_what_ended_ok_at_each_place(interface, golden_run):
    golden, trace, _ = golden_run
    timeline = ScriptTimeline(golden, trace, interface.replies)
    steps = [s.render() for s in golden.steps]
    assert timeline.ended_ok(0) == set() and timeline.running(1, ["rflex.Init"])  # Init just sent
    after_inits = steps.index("wait all") + 1
    assert {"rflex.Init", "ndd.Init", "antenna.Init"} <= timeline.ended_ok(after_inits)
    goto = steps.index("send ndd.GotoPosition x=9 y=4 as site1")
    assert [a.service for a in timeline.running(goto, ["rflex.TrackSpeedStart", "aspect.Fuse"])] == \
        ["rflex.TrackSpeedStart", "aspect.Fuse"]
    assert timeline.running(goto + 1, ["ndd.GotoPosition"])  # between send and wait: it runs
    assert not timeline.running(goto + 2, ["ndd.GotoPosition"])  # after its wait: it ended
    assert timeline.start == sorted(timeline.start)


def test_same_seed_same_bytes_and_every_mutant_names_its_aim(interface, properties, golden_run):
    golden, trace, verdicts = golden_run
    first = targeted.generate(GoldenRun(golden, trace, verdicts), interface, properties, aimed(60, 5))
    again = targeted.generate(GoldenRun(golden, trace, verdicts), interface, properties, aimed(60, 5))
    other = targeted.generate(GoldenRun(golden, trace, verdicts), interface, properties, aimed(60, 6))
    assert [(m.body, m.operations) for m in first] == [(m.body, m.operations) for m in again]
    assert [m.body for m in first] != [m.body for m in other]
    assert len({m.body for m in first}) == 60 and all(m.valid for m in first)
    ids = {p.id for p in properties}
    for m in first:
        aims = {op["aim"] for op in m.operations}
        assert len(aims) == 1 and aims <= ids and 1 <= len(m.operations) <= targeted.SITES_PER_MUTANT
        json.dumps(m.operations)  # stored as scripts.mutations
    # balance: the golden already falsifies 3 AIB conditions (its final Stops); the others come first
    falsified = {v["property_id"] for v in verdicts if v["c_holds"] is False}
    first_aims = [m.operations[0]["aim"] for m in first[:len(ids) - len(falsified)]]
    assert sorted(first_aims) == sorted(ids - falsified)


TOY_INTERFACE = """
[replies]
ok = "T"
stopped = "Z"
not_ready = "R"
[modules.arm]
services.Init = { kind = "init" }
services.Move = { kind = "exec", args = { angle = { type = "float", min = 0.0, max = 90.0 } } }
services.Stop = { kind = "exec" }
[modules.gripper]
services.Close = { kind = "exec" }
"""
TOY_PROPERTIES = """
[[property]]
id = "READY"
family = "R"
type = "PC"
x = ["arm.Move"]
q = ["arm.Init"]
r_p = "not_ready"
[[property]]
id = "STOPS"
family = "S"
type = "EE"
x = ["arm.Move"]
y = ["arm.Stop"]
z_p = "stopped"
"""
TOY_GOLDEN = "send arm.Init as i\nwait i\nsend arm.Move angle=45 as m\nwait m\nsend gripper.Close\n"


def test_generation_reads_only_data_a_made_up_mission_works(tmp_path):
    (tmp_path / "interface.toml").write_text(TOY_INTERFACE)
    (tmp_path / "properties.toml").write_text(TOY_PROPERTIES)
    interface = load_interface(tmp_path / "interface.toml")
    properties = load_properties(tmp_path / "properties.toml", interface)
    golden = parse(TOY_GOLDEN)
    # Init 0-1 s, Move 1.02-5 s, Close 5.04-6 s, as a black-box log would show them
    events = [(1, 0.0, "request", 1, "arm", "Init", "{}", None), (2, 1.0, "final", 1, "arm", "Init", None, "ok"),
              (3, 1.02, "request", 2, "arm", "Move", "{}", None), (4, 5.0, "final", 2, "arm", "Move", None, "ok"),
              (5, 5.04, "request", 3, "gripper", "Close", "{}", None),
              (6, 6.0, "final", 3, "gripper", "Close", None, "ok")]
    trace = Trace("toy", 0, events=events)
    mutants = targeted.generate(GoldenRun(golden, trace, []), interface, properties, aimed(20, 1))
    assert all(m.valid for m in mutants)
    assert {op["aim"] for m in mutants for op in m.operations} == {"READY", "STOPS"}
    for m in mutants:
        steps = [s.render() for s in m.script.steps]
        for op in m.operations:
            at = op["position"] - 1
            if op["aim"] == "READY":  # a Move before Init's ok: before the wait on it
                assert steps[at].startswith("send arm.Move") and at < steps.index("wait i")
            elif "while arm.Move runs" in op["situation"]:  # the golden's Move: between its send and wait
                assert steps.index("send arm.Move angle=45 as m") < at < steps.index("wait m")


@pytest.mark.slow
def test_targeted_campaign_reaches_every_property_30_times_on_reference(tmp_path, properties, capsys):
    db = tmp_path / "t.duckdb"
    assert main(["campaign", "--strategy", "targeted", "--sut", "reference", "--db", str(db), "--jobs", "2"]) == 0
    con = store.connect(db, read_only=True)
    covered = dict(con.execute("select property_id, c_false from coverage where sut = 'reference'").fetchall())
    assert set(covered) == {p.id for p in properties}
    values = {p.id for p in properties if p.type in targeted.VALUE_TYPES}  # aimed at with --value-mutations only
    assert min(n for p, n in covered.items() if p not in values) >= 30, covered
    assert {covered[p] for p in values} == {0}
    config = json.loads(con.execute("select config from campaigns").fetchone()[0])
    assert (config["strategy"], config["ops_per_mutant"]) == ("targeted", targeted.SITES_PER_MUTANT)
    assert "Least covered (requests with C false" in capsys.readouterr().out


def _args(**changes):
    values = dict(mission=str(DEFAULT_MISSION_DIR), mutants=3, sut="genom", seed=1, jobs=1, ops_per_mutant=None,
                  strategy="random", time_mutations=False, value_mutations=False, operators=None, max_delay=0.003,
                  time_scale=None)
    return CampaignRequest(**{**values, **changes})


def _config(request: CampaignRequest):
    mission = load_mission(request.mission)
    return campaign_config(request, mission, mission.golden())


def test_strategy_is_part_of_the_campaign_and_time_mutations_stay_random():
    assert _config(_args()).ops_per_mutant == 1
    with pytest.raises(UntimelyError, match="--time-mutations applies to --strategy random only"):
        _config(_args(strategy="targeted", time_mutations=True))
    con = store.connect()
    old = {k: v for k, v in _config(_args()).stored().items() if k != "strategy"}  # made before --strategy
    store.add_campaign(con, 1, "m", 1, record_of(old))
    assert find_campaign(con, _config(_args()), "db") == 1
    with pytest.raises(StoreError, match="made with --strategy random, not targeted"):
        find_campaign(con, _config(_args(strategy="targeted")), "db")


def test_operators_are_part_of_the_campaign_and_stay_random():
    config = _config(_args(operators="swap_requests,delete_request"))
    assert config.operators == ["delete_request", "swap_requests"]
    assert _config(_args()).operators is None
    with pytest.raises(UntimelyError, match="--operators applies to --strategy random only"):
        _config(_args(strategy="targeted", operators="swap_requests"))
    con = store.connect()
    store.add_campaign(con, 1, "m", 1, record_of({k: v for k, v in _config(_args()).stored().items()
                                                  if k != "operators"}))  # made before --operators
    assert find_campaign(con, _config(_args()), "db") == 1
    with pytest.raises(StoreError, match=r"made with --operators \(the default\), not delete_request,swap_requests"):
        find_campaign(con, config, "db")
