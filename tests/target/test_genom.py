"""The GenoM3 reader (harness/target/genom/) on one hand-made description per construct: what it
reads right, and what it refuses naming the file, the line and the construct."""
import tomllib

import pytest

from harness.cli import main
from harness.store import connect
from harness.target.interface import load_interface, load_properties
from harness.target.mission import load_mission
from tests.support.paths import GENOM


def _init(tmp_path, text, capsys=None, files=None):
    gen = tmp_path / "c.gen"
    gen.write_text(text)
    for name, content in (files or {}).items():
        (tmp_path / name).write_text(content)
    folder = tmp_path / "t"
    status = main(["init", str(folder), "--from-genom", str(gen)])
    return status, folder, gen


def _properties(folder):
    interface = load_interface(folder / "interface.toml")
    return interface, {p.id: p for p in load_properties(folder / "properties.toml", interface)}


def test_braces_in_a_default_value_keep_the_clauses_that_follow(tmp_path):
    status, folder, _ = _init(tmp_path, """component c {
  function S();
  activity A(in string<64> serial[2] = { "a", "b" }: "ports", in double v = 1.0) {
    interrupts A;
    after S;
  };
};""")
    assert status == 0
    _, properties = _properties(folder)
    assert properties["AIB(c.A)"].y == ("c.A", "c.kill")
    assert properties["PEX(c)"].q == ("c.S",) and properties["PEX(c)"].r_p == "disallowed"
    assert "#   from c.gen:5: c.A after S\n[[property]]\nid = \"PEX(c)\"" in (folder / "properties.toml").read_text()


def test_comment_markers_inside_strings_are_text(tmp_path):
    status, folder, _ = _init(tmp_path, """component c {
  activity A(in string<8> tag = "#1") {
    doc "see http://example.org/a // not a comment";
    interrupts A;
  };
  activity B() { doc "# neither"; interrupts B; };
};""")
    assert status == 0
    interface, properties = _properties(folder)
    assert {"c.A", "c.B"} <= set(interface.services)
    assert not any(p.startswith(("PRE", "PEX")) for p in properties), "no precondition is invented"
    assert properties["AIB(c.B)"].y == ("c.B", "c.kill")


def test_before_is_a_precondition_of_the_listed_services_citing_its_line(tmp_path):
    status, folder, gen = _init(tmp_path, """component c {
  activity Go();
  activity Look();
  function Setup() {
    before Look;
  };
};
component d {
  activity Go();
  function Setup() { before Go; };
};
component e {
  activity Only();
  function Then() { after Only; };
};""")
    assert status == 0
    _, properties = _properties(folder)
    assert properties["PRE(c.Look)"].q == ("c.Setup",) and "PRE(c.Go)" not in properties
    assert "PEX(c)" not in properties, "Go needs nothing: Setup is no init service"
    assert properties["PEX(d)"].q == ("d.Setup",) and properties["PEX(d)"].x == ("d.Go",)
    assert "PEX(e)" not in properties and properties["PRE(e.Then)"].q == ("e.Only",), "no activity needs Only"
    assert "#   from c.gen:10: d.Setup before Go\n[[property]]\nid = \"PEX(d)\"" in \
        (folder / "properties.toml").read_text()
    assert "#   from c.gen:5: c.Setup before Look" in (folder / "properties.toml").read_text()
    golden = (folder / "golden.mission").read_text()
    assert golden.index("send c.Setup") < golden.index("send c.Look")


def test_provides_of_an_included_interface_brings_its_services(tmp_path):
    status, folder, _ = _init(tmp_path, """#include "iface.gen"
component c {
  provides iface;
  activity Own();
};""", files={"iface.gen": "interface iface {\n  activity Run() { interrupts Run; };\n"
                           "  function Halt() { interrupts Run; };\n};\n"})
    assert status == 0
    interface, properties = _properties(folder)
    assert interface.services["c.Run"].kind == "exec" and interface.services["c.Halt"].kind == "control"
    assert set(properties["AIB(c.Run)"].y) == {"c.Run", "c.Halt", "c.kill"}


def test_defines_and_conditionals_are_preprocessed(tmp_path):
    status, folder, _ = _init(tmp_path, """#define STOPPER halt
#ifdef NOT_DEFINED
component broken {
#endif
component c {
  activity Go();
  function STOPPER() { interrupts Go; };
};""")
    assert status == 0
    assert set(_properties(folder)[1]["AIB(c.Go)"].y) == {"c.halt", "c.kill"}


def test_pragma_provides_applies_to_every_component_and_other_pragmas_are_named(tmp_path, capsys):
    status, folder, _ = _init(tmp_path, """#pragma require "openrobots2-idl >= 2.0"
interface iface { activity Run(); };
component c { activity Own(); };
#pragma provides iface
""")
    assert status == 0
    assert "c.Run" in load_interface(folder / "interface.toml").services
    assert '#pragma require "openrobots2-idl >= 2.0" (c.gen:1) concerns genom3\'s build' in capsys.readouterr().out


def test_exceptions_with_nested_members_make_valid_toml_and_validate_only_ones_are_rejections(tmp_path):
    status, folder, _ = _init(tmp_path, """component c {
  exception e_x { struct inner { double a; } s; long n; }, e_y;
  exception e_range;
  attribute set(in v = 1.0) { validate check(local in v); throw e_range; };
  activity A() { throw e_x, e_y; };
};""")
    assert status == 0
    replies = tomllib.loads((folder / "interface.toml").read_text())["replies"]
    assert (replies["e_x"], replies["e_y"], replies["e_range"]) == ("T", "T", "R")


def test_services_differing_by_case_are_two_services_and_the_golden_run_completes(tmp_path, capsys):
    status, folder, _ = _init(tmp_path, "component c { activity Move(); activity move(); };")
    assert status == 0
    assert {"c.Move", "c.move"} <= set(load_mission(folder).interface.services)
    assert main(["run", str(folder / "golden.mission"), "--sut", "adapter", "--db", str(tmp_path / "r.duckdb")]) == 0
    assert "outcome    completed" in capsys.readouterr().out


@pytest.mark.parametrize("text, files, line, words", [
    ("component c {\n  exception e_a e_b;\n  activity A();\n};", {}, 2,
     "cannot read 'exception e_a e_b;' at column 17: the dotgen grammar expects ',' or '{' or ';' there"),
    ("component c {\n  activity A() {\n    interrupts A;\n", {}, 3, "the file ends inside a declaration"),
    ("component c { activity A(); };\n\ncomponent c { activity B(); };", {}, 3, "declared twice (first at c.gen:1)"),
    ('#include "loop.gen"\ncomponent c { activity A(); };', {"loop.gen": '#include "loop.gen"\n'}, None,
     "an #include loop"),
    ("component c {\n  activity A();\n  /* never closed\n};", {}, 3, "comment that never ends"),
    ('#include "absent.gen"\ncomponent c { activity A(); };', {}, 1, "give its folder with --include DIR"),
    ("component c { provides nowhere; activity A(); };", {}, 1, "an interface that no file read declares"),
    ("component c {\n  activity A();\n  function A();\n};", {}, 3, "service A is declared twice in c (first at c.gen:2)"),
    ("component c { function f(); attribute g(); };", {}, 1, "states no property untimely can judge"),
])
def test_what_cannot_be_read_is_refused_naming_file_line_and_construct(tmp_path, capsys, text, files, line, words):
    status, folder, gen = _init(tmp_path, text, files=files)
    out = capsys.readouterr()
    assert status == 2 and words in out.err, out.err
    assert str(gen if line else tmp_path) in out.err and (line is None or f"{gen}:{line}:" in out.err)
    assert not folder.exists() and "next:" not in out.out


@pytest.mark.slow
def test_three_hand_made_components_read_as_their_clauses_say(tmp_path, capsys):
    """tests/genom/{wheelbase,quadmotors,maneuver2}.gen, checked by hand against their lines."""
    genom = GENOM
    found = {}
    for name in ("wheelbase", "quadmotors", "maneuver2"):
        assert main(["init", str(tmp_path / name), "--from-genom", str(genom / f"{name}.gen"),
                     "--include", str(genom / "include")]) == 0
        found[name] = _properties(tmp_path / name)
    out = capsys.readouterr().out
    interface, p = found["wheelbase"]
    assert {s: interface.services[s].kind for s in interface.services if s.endswith(("Init", "Track", "Stop"))} == {
        "wheelbase.Init": "init", "wheelbase.Track": "exec", "wheelbase.Stop": "control"}
    assert p["PEX(wheelbase)"].x == ("wheelbase.Track", "wheelbase.Goto")
    assert p["PEX(wheelbase)"].q == ("wheelbase.Init",)
    assert p["PRE(wheelbase.Track)"].q == ("wheelbase.SetSpeedLimits",), "after Init (line 49) is PEX's"
    assert p["AIB(wheelbase.Goto)"].y == ("wheelbase.Track", "wheelbase.Goto", "wheelbase.Stop", "wheelbase.kill")
    assert interface.replies["e_emergency"] == "T" and interface.replies["e_sys"] == "T"
    interface, p = found["quadmotors"]
    assert "PEX(quadmotors)" not in p, "stop (line 39) comes after nothing: no service every activity needs"
    assert p["PRE(quadmotors.start)"].q == ("quadmotors.init",)
    assert p["PRE(quadmotors.servo)"].q == ("quadmotors.start",)
    assert "quadmotors.servo (quadmotors.gen:36) interrupts 'spin_down', which the component does not declare" in out
    assert "e_started" in interface.replies, "an exception declared after one with members"
    _, p = found["maneuver2"]
    assert p["PRE(maneuver2.goto)"].q == ("maneuver2.set_current_state", "maneuver2.set_bounds")
    assert p["PRE(maneuver2.waypoint)"].q == ("maneuver2.goto",)
    assert p["AIB(maneuver2.set_current_state)"].y == ("maneuver2.stop", "maneuver2.kill"), "stop interrupts all"
    db = tmp_path / "w.duckdb"
    assert main(["campaign", "--mission", str(tmp_path / "wheelbase"), "--sut", "adapter", "--mutants", "10",
                 "--db", str(db)]) == 0
    con = connect(db, read_only=True)
    golden = con.execute("select count(*) filter (verdict in ('FN', 'FP')), count(*) filter (verdict = 'TN') "
                         "from verdicts join traces using (trace_id) join scripts using (script_id) "
                         "where kind = 'golden'").fetchone()
    certain = con.execute("select count(*) from verdicts where verdict in ('FN', 'FP') and certain").fetchone()[0]
    con.close()
    assert golden[0] == 0 and golden[1] > 0, "the golden run waits for each ok another request needs"
    assert certain == 0, "the stand-in follows PEX, PRE and AIB"


def test_validate_codels_state_the_arguments_they_check_and_their_rejection(tmp_path, capsys):
    """tests/genom/validating.gen, checked by hand against its lines: what each validate codel states."""
    folder = tmp_path / "ptu"
    assert main(["init", str(folder), "--from-genom", str(GENOM / "validating.gen")]) == 0
    out = capsys.readouterr().out
    interface, p = _properties(folder)
    assert {a: (v.type, v.min, v.max) for a, v in interface.services["ptu.set_speed"].args.items()} == {
        "speed": ("float", None, None), "mode": ("str", None, None)}, "the bounds are the codel's C code"
    assert [(a.name, a.type) for a in interface.services["ptu.point"].args.values()] == [("pan", "float"),
                                                                                          ("tag", "str")], \
        "pan unqualified names the parameter; tilt is an array; mode (line 15) is the ids member"
    assert not any(interface.services[f"ptu.{s}"].args for s in ("either", "silent", "scan", "init"))
    assert (p["VAL(ptu.set_speed)"].r_p, p["VAL(ptu.point)"].r_p) == ("e_range", "e_busy")
    assert interface.replies["e_range"] == interface.replies["e_busy"] == "R" and interface.replies["e_io"] == "T"
    assert not {"VAL(ptu.either)", "VAL(ptu.silent)", "VAL(ptu.scan)"} & set(p)
    assert p["PRE(ptu.set_speed)"].q == ("ptu.init",) and p["PRE(ptu.set_speed)"].r_p == "disallowed"
    text = (folder / "properties.toml").read_text()
    assert "#   from validating.gen:10: ptu.set_speed validate ptu_check(speed, mode)\n" \
           "#   from validating.gen:11: ptu.set_speed throw e_range\n[[property]]\nid = \"VAL(ptu.set_speed)\"" in text
    assert "validating.gen:15: ptu.point validate ptu_point reads the component's state (mode): it may reject a " \
           "request that came too early with e_busy, but no after or before clause says" in out
    assert "ptu.set_speed validate ptu_check reads" not in out, "its precondition is written: after init (line 12)"
    assert "validating.gen:15: ptu.point validate ptu_point checks `in double tilt`" in out
    assert "validating.gen:18: ptu.either validate ptu_either: it may reject with any of e_a, e_b" in out
    assert "validating.gen:19: ptu.silent validate ptu_silent: the service throws no exception of its own" in out
    assert "e_io may come from the validate codel of scan (a rejection) or from their other codels" in out
    golden = (folder / "golden.mission").read_text()
    assert "send ptu.set_speed speed=0.5 mode=fast\n" in golden and 'send ptu.point pan=0 tag=""\n' in golden
    assert "[[validates]]\nx = [\"ptu.point\"]\nreply = \"e_busy\"" in (folder / "standin.toml").read_text()
    (folder / "values.mission").write_text("send ptu.init\nwait all timeout=30\nsend ptu.set_speed speed=nan "
                                           "mode=fast\nsend ptu.set_speed speed=2 mode=slow\nsend ptu.point pan=far "
                                           "tag=a\nsend ptu.point pan=1 tag=b\nwait all timeout=30\n")
    db = tmp_path / "v.duckdb"
    assert main(["run", str(folder / "values.mission"), "--sut", "adapter", "--db", str(db)]) == 0
    assert main(["analyze", "--db", str(db)]) == 0
    con = connect(db, read_only=True)
    verdicts = con.execute("select property_id, verdict, count(*) from verdicts where property_id like 'VAL%' "
                           "group by all order by all").fetchall()
    con.close()
    assert verdicts == [("VAL(ptu.point)", "TN", 1), ("VAL(ptu.point)", "TP", 1), ("VAL(ptu.set_speed)", "TN", 1),
                        ("VAL(ptu.set_speed)", "TP", 1)], "the stand-in rejects nan and a word for a number"


def test_a_component_whose_only_clause_is_a_rejecting_validate_gets_its_val_and_a_golden_run(tmp_path, capsys):
    status, folder, _ = _init(tmp_path, """component c {
  exception e_range;
  function set(in double gain = 2.5 : "proportional gain") {
    validate check_gain(local in gain);
    throw e_range;
  };
};""")
    assert status == 0, "no activity and no after or before clause, but a validate codel that rejects"
    interface, properties = _properties(folder)
    assert list(properties) == ["VAL(c.set)"] and properties["VAL(c.set)"].r_p == "e_range"
    assert interface.services["c.set"].args["gain"].type == "float"
    assert "send c.set gain=2.5\n" in (folder / "golden.mission").read_text()
    assert main(["run", str(folder / "golden.mission"), "--sut", "adapter", "--db", str(tmp_path / "g.duckdb")]) == 0
    assert "replies    T 1, Z 0, R 0" in capsys.readouterr().out, "the golden value lies in the domain"
