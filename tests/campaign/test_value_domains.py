"""Value-domain robustness (issue 25): a value-mutation campaign on Dala's variants, whose VAL
family shows what each variant's argument checks predict, and the external protocol carrying
arguments unchanged to adapters that check domains and that do not."""
import json

import pytest

from harness import DEFAULT_MISSION_DIR, cli, store
from harness.analysis.judge import Judge
from harness.target.suts import ExternalSut
from harness.mutator import strategies
from harness.sut.executive import run_script
from harness.store.record import CampaignRecord
from harness.sut.external.runner import run_external
from harness.target.domains import violation
from harness.target.mission import load_mission
from harness.target.script import parse
from tests.support.paths import ADAPTERS

ADAPTER = ADAPTERS / "domains.py"
# In domain, then every way out of it; one request each, each after the modules' Init.
VALUES = """send ndd.Init as ni
send rflex.Init as ri
wait all
send ndd.SetParams speed=0.5 as in_domain
send ndd.GotoPosition x=0 y=20 as bounds
send ndd.SetParams speed=1.001 as above
send ndd.GotoPosition x=nan y=4 as nan
send ndd.GotoPosition x=3 y=-inf as minus_inf
send ndd.GotoPosition x=east y=4 as wrong_type
send ndd.GotoPosition x=3 as missing
send rflex.SetMode mode="" as empty
send rflex.SetMode mode=0 as number_text
wait all
"""
IN_DOMAIN = {3, 4}  # request ids of the legal values; 1 and 2 are the Inits


@pytest.fixture(scope="module")
def value_campaign(tmp_path_factory):
    db = tmp_path_factory.mktemp("values") / "c.duckdb"
    assert cli.main(["campaign", "--mutants", "40", "--value-mutations", "--sut", "reference,genom,bare",
                     "--seed", "3", "--jobs", "2", "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    yield con
    con.close()


@pytest.mark.slow
def test_the_val_family_is_caught_by_reference_and_missed_by_bare(value_campaign):
    rates = dict(value_campaign.execute("select sut, tp * 100.0 / (tp + fn) from tp_rates where family = 'VAL'")
                 .fetchall())
    assert rates["reference"] == 100.0 and rates["bare"] == 0.0
    assert 0.0 < rates["genom"] < 100.0


@pytest.mark.slow
def test_genom_catches_exactly_the_numbers_out_of_range(value_campaign, interface):
    """genom checks static ranges only (layer.toml RANGE): a finite number or an infinity beyond
    a bound is rejected (TP); nan, a word that is no number, a missing argument, a text outside
    its choices pass (FN), unless another protection rejects the request first (op)."""
    services = interface.services
    rows = value_campaign.execute("""
        select v.verdict, s.mutations from verdicts v join traces t using (trace_id) join scripts s using (script_id)
        where t.sut = 'genom' and v.family = 'VAL' and not v.c_holds""").fetchall()
    seen = {"range": set(), "other": set()}
    for verdict, mutations in rows:
        (op,) = [m for m in json.loads(mutations) if m["op"] == "replace_value"]
        service = parse(op["step"]).steps[0].service
        broken = violation(services[service].args[op["argument"]], op["value"])
        seen["range" if broken == "range" else "other"].add(verdict)
    assert seen == {"range": {"TP"}, "other": {"FN"} | (seen["other"] & {"op"})}
    assert seen["other"] >= {"FN"}


def _external(check: bool, tmp_path) -> tuple:
    log = tmp_path / f"args-{check}.jsonl"
    command = f"{{python}} {ADAPTER} --interface {DEFAULT_MISSION_DIR / 'interface.toml'} --log {log}"
    sut = ExternalSut("checks" if check else "lets-through", command=command + (" --check" if check else ""),
                      time_scale=10.0, probe_timeout_s=2.0, startup_s=10.0)
    return sut, log


@pytest.mark.parametrize("check", [True, False], ids=["checking adapter", "unchecking adapter"])
def test_the_protocol_carries_arguments_unchanged_and_val_judges_the_adapter(interface, properties, tmp_path, check):
    sut, log = _external(check, tmp_path)
    trace = run_external(parse(VALUES, "values"), sut, 1, interface, slot=0)
    assert trace.outcome == "completed", trace.error
    received = {r["id"]: r["args"] for r in map(json.loads, log.read_text().splitlines())}
    stored = {e[3]: json.loads(e[6]) for e in trace.events if e[2] == "request"}
    assert received == stored
    assert stored[5] == {"speed": 1.001} and stored[6] == {"x": "nan", "y": 4.0}
    assert stored[7] == {"x": 3.0, "y": "-inf"} and stored[8] == {"x": "east", "y": 4.0}
    assert stored[9] == {"x": 3.0} and stored[10] == {"mode": ""} and stored[11] == {"mode": "0"}
    val = [p for p in properties if p.family == "VAL"]
    verdicts = {v["rqst_id"]: v["verdict"] for v in Judge(interface, val).verdicts([trace])[0]}
    assert sorted(verdicts) == list(range(3, 12))
    for rqst_id, verdict in verdicts.items():
        expected = "TN" if rqst_id in IN_DOMAIN else ("TP" if check else "FN")
        assert verdict == expected, (rqst_id, verdict)


@pytest.mark.slow
def test_targeted_mutants_exercise_the_manipulators_state_dependent_domain(tmp_path):
    """SLOW(base.Move): no move faster than 0.3 m/s while the arm is deployed. Targeted mutants
    send fast moves while a Deploy runs; `safe` refuses them (SLOW in its layer.toml), `careless`
    does not (FN)."""
    db = tmp_path / "m.duckdb"
    assert cli.main(["campaign", "--mission", str(DEFAULT_MISSION_DIR.parent / "manipulator"), "--strategy",
                     "targeted", "--value-mutations", "--mutants", "16", "--sut", "safe,careless", "--seed", "5",
                     "--jobs", "2", "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    aims = [m for body, in con.execute("select mutations from scripts where kind = 'mutant'").fetchall()
            for m in json.loads(body) if m["aim"] == "SLOW(base.Move)"]
    assert aims and all("base.Move while" in m["situation"] and "arm.Deploy" in m["situation"] for m in aims)
    verdicts = dict(con.execute("""select sut, list(verdict order by verdict) from verdicts join traces using (trace_id)
                                   where property_id = 'SLOW(base.Move)' and not c_holds group by sut""").fetchall())
    con.close()
    assert "FN" in verdicts["careless"] and "FN" not in verdicts["safe"] and "TP" in verdicts["safe"]


@pytest.mark.slow
def test_a_focused_campaign_aims_at_the_value_domains(tmp_path):
    """--strategy focused --value-mutations: a VAL aim's test is its request's preconditions from the
    golden, then the request with one exceptional value. `reference` rejects every value outside
    its domain (TP, never FN or FP); `bare` takes them, a finding."""
    db = tmp_path / "fv.duckdb"
    assert cli.main(["campaign", "--strategy", "focused", "--value-mutations", "--mutants", "50", "--budget",
                     "1500s", "--sut", "reference,bare", "--seed", "3", "--jobs", "2", "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    tests = [(json.loads(m)[0], body) for m, body in
             con.execute("select mutations, body from scripts where kind = 'mutant'").fetchall()]
    aims = [(m, body) for m, body in tests if m["aim"].startswith("VAL(")]
    assert aims and all(" with " in m["situation"] for m, _ in aims)
    assert all(len(parse(body).steps) <= 7 for _, body in aims)
    verdicts = dict(con.execute("""select sut, list(distinct verdict order by verdict) from verdicts
                                   join traces using (trace_id) where family = 'VAL' group by sut""").fetchall())
    findings = con.execute("select sut, property_id, kind from findings where property_id like 'VAL(%'").fetchall()
    con.close()
    assert "TP" in verdicts["reference"] and not {"FN", "FP"} & set(verdicts["reference"])
    assert "FN" in verdicts["bare"] and "TP" not in verdicts["bare"]
    assert {(sut, kind) for sut, _, kind in findings} == {("bare", "FN")}
    assert {p for _, p, _ in findings} == {"VAL(rflex)", "VAL(sick)", "VAL(ndd)", "VAL(antenna)"}


def test_focused_tests_send_the_manipulators_fast_moves_while_the_arm_is_deployed():
    """SLOW(base.Move)'s focused aims: moves legal at rest, each in the start phase of a fresh
    arm.Deploy and while it runs, then the golden's arm.Stop; outside 0.3 m/s they falsify C,
    inside they are disturbances. Without --value-mutations the plan has no value aim."""
    folder = DEFAULT_MISSION_DIR.parent / "manipulator"
    target = load_mission(folder)
    golden, interface, properties = target.golden(), target.interface, target.properties()
    trace = run_script(golden, "safe", 1, interface, target.world_file)
    plans = {flag: strategies.plan(CampaignRecord(mission=str(folder), mutants=0, sut=["safe"], seed=7,
                                                  ops_per_mutant=1, strategy="focused", value_mutations=flag),
                                   golden, interface, properties, trace)
             for flag in (False, True)}
    assert not [a for a in plans[False].aims if a.value]
    slow = [(n, a) for n, a in enumerate(plans[True].aims) if a.properties == ("SLOW(base.Move)",)]
    assert {(a.phase, a.other) for _, a in slow} == {("start", "arm.Deploy"), ("running", "arm.Deploy")}
    for n, aim in slow:
        argument, kind, word = aim.value
        assert argument == "speed" and 0.05 <= float(word) <= 1.0 and aim.disturb == (float(word) <= 0.3)
        test = plans[True].test(n, "test")
        steps = [s.service for s in test.script.steps if s.op == "send"]
        assert test.valid and steps[-3:] == ["arm.Deploy", "base.Move", "arm.Stop"]
        assert f"base.Move speed={word}" in test.body
