"""The GenoM3 reader on the constructs of genom3's own regression descriptions (issue 48): types
declared in place in a service's parameters (structs, unions, enums, sequences, arrays) with
nested initialisers, and a file of data types without a component, refused naming the file.
Each description is written here, of the kind genom3's regression suite holds."""
import pytest

from harness.cli import main
from harness.target.genom.reader import read_scopes
from harness.target.mission import load_mission

ARM = "component arm {{\n  exception e_bad;\n  ids {{ long count; }};\n  {service}\n  activity Stop();\n}};\n"


def _read(tmp_path, service: str) -> dict:
    """The parameters of service `s` of a component declaring it, as the reader makes them."""
    gen = tmp_path / "arm.gen"
    gen.write_text(ARM.format(service=service))
    components, _, _ = read_scopes(gen, [])
    return {p.name: p for p in components[0].services["s"].params}


@pytest.mark.parametrize("service, name, written", [
    ("function s(inout struct param { long x; double y; } b[3] = {{0}, {1, 2.0}, {.x = 3}});", "b",
     "inout struct param b"),
    ("function s(in enum colour { red, green, blue } c = green : \"the colour\");", "c", "in enum colour c"),
    ("function s(in union pick switch (boolean) { case TRUE: long n; case FALSE: double d; } p);", "p",
     "in union pick switch p"),
    ("function s(in sequence<sequence<double, 3>, 8> points);", "points", "in sequence points"),
    ("function s(in string<16> names[2] = { \"a\", \"b\" });", "names", "in string names"),
    ("function s(in double grid[2][3] = { { 1, 2, 3 }, { 4, 5, 6 } });", "grid", "in double grid"),
    ("activity s(in struct goal { double pos[3]; struct tol { double lin, ang; } t; } g = "
     "{ .pos = { 1, 2, 3 }, .t = { 0.1, 0.2 } }) { interrupts s; throw e_bad; };", "g", "in struct goal g"),
])
def test_a_type_declared_in_a_parameter_is_read_and_not_carried(tmp_path, service, name, written):
    params = _read(tmp_path, service)
    assert list(params) == [name] and params[name].written == written
    assert params[name].type is None and params[name].default is None  # a compound: no mission word carries it


def test_a_plain_parameter_after_an_inline_type_keeps_its_type_and_default(tmp_path):
    params = _read(tmp_path, "function s(in struct p { long x; } a = {{0}}, in double speed = 0.5 : \"m/s\");")
    assert (params["speed"].type, params["speed"].default, params["speed"].doc) == ("float", "0.5", "m/s")


@pytest.mark.slow
def test_a_component_with_types_declared_in_its_parameters_gets_a_target_that_runs_a_campaign(tmp_path, capsys):
    gen = tmp_path / "arm.gen"
    gen.write_text(ARM.format(service="activity s(inout struct param { long x; } b[3] = {{0}}, in enum e { a, b } "
                                       "m = a) { interrupts s; };"))
    folder = tmp_path / "target"
    assert main(["init", str(folder), "--from-genom", str(gen)]) == 0
    assert {"arm.s", "arm.Stop"} <= set(load_mission(folder).interface.services)
    db = tmp_path / "c.duckdb"
    assert main(["campaign", "--mission", str(folder), "--sut", "adapter", "--mutants", "2", "--db", str(db)]) == 0
    assert "adapter   3 runs: 3 completed" in capsys.readouterr().out


TYPES_ONLY = """/* data types only, as a component #includes them */
interface shapes {
  typedef sequence<double, 6> pose6;
  struct corner { double x, y; string<16> label[2]; };
  native handle;
  exception bad_shape { string<32> why; };
};
module geo { enum axis { ax_x, ax_y, ax_z }; const long dims = 3; };
typedef long grid[2][3];
const geo::axis main_axis = geo::ax_z;
union choice switch (geo::axis) {
  case geo::ax_x: short a[2];
  default: enum inner { i1, i2 } c;
};
struct later;
typedef struct later { choice a; sequence<corner, 4> b; } later_t;
"""


@pytest.mark.parametrize("text, words", [
    (TYPES_ONLY, "no `component NAME { ... };` found (it declares the interfaces shapes)"),
    # a service written outside any component: lark's own end-of-file marker among what it expected
    # made the message itself crash (KeyError '$END')
    ("typedef long x;\nattribute a = 0;\n", "expects the end of the file or"),
])
def test_a_file_without_a_component_is_refused_naming_it(tmp_path, capsys, text, words):
    gen = tmp_path / "types.gen"
    gen.write_text(text)
    assert main(["init", str(tmp_path / "t"), "--from-genom", str(gen)]) == 2
    err = capsys.readouterr().err
    assert words in err and str(gen) in err and "crashed" not in err, err
    assert not (tmp_path / "t").exists()
