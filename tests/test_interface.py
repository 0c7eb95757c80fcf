import pytest

from harness.errors import InputFileError
from harness.target.interface import load_interface, load_properties

GOOD = """
[replies]
ok = "T"
interrupted = "Z"
wait_init = "R"
[modules.m]
services.Init = { kind = "init" }
services.Go = { kind = "exec", args = { v = { type = "float", min = 0.0, max = 1.0 } } }
"""


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_dala_interface_and_21_properties(interface, properties):
    assert interface.modules == ["rflex", "sick", "aspect", "ndd", "antenna"]
    assert interface.services["ndd.GotoPosition"].kind == "exec"
    assert interface.replies["interrupted_excl"] == "Z"
    assert len(properties) == 21
    families = {}
    for p in properties:
        families[p.family] = families.get(p.family, 0) + 1
    assert families == {"PEX": 5, "AIB": 7, "PRE": 6, "EXC": 3}
    assert {p.type for p in properties} == {"PC", "EE", "MX_I"}
    assert interface.until_stopped == ["rflex.TrackSpeedStart", "sick.ContinuousShot", "aspect.Fuse"]
    assert interface.of_kind("control") == ["rflex.SetMode", "sick.SetParams", "ndd.SetParams", "antenna.SetChannel"]


@pytest.mark.parametrize("text, message", [
    (GOOD.replace('interrupted = "Z"', 'interrupted = "X"'), "[replies] interrupted: class 'X' is not one of T, Z, R"),
    (GOOD.replace('kind = "exec"', 'kind = "run"'), "[modules.m] services.Go: kind 'run' is not one of init, control, exec"),
    (GOOD.replace("max = 1.0", "max = -1.0"), "argument 'v' needs numeric min <= max, got min=0.0 max=-1.0"),
    (GOOD.replace('ok = "T"', ""), "the catalogue must contain ok"),
    (GOOD.replace('ok = "T"', 'ok = "R"'), "the catalogue must contain ok = \"T\", not ok = 'R'"),
    (GOOD.replace('kind = "exec", args', 'kind = "exec", agrs'),
     "[modules.m] services.Go: unknown key(s) ['agrs']; a service takes kind, args, until_stopped, doc"),
    (GOOD.replace("[modules.m]", "[modules.m]\nposter = \"P\"\nposters = \"Q\""),
     "[modules.m]: unknown key(s) ['posters']; a module takes doc, poster, services"),
    (GOOD.replace("max = 1.0", "max = 1.0, choices = [\"a\"]"),
     "services.Go args.v: unknown key(s) ['choices']; a float argument takes type, min, max, doc"),
    (GOOD + "[reply]\nok = \"T\"\n", "top level: unknown key(s) ['reply']; the top level takes replies, modules"),
    ("[replies\n", "not valid TOML"),
    (GOOD.replace('kind = "exec"', 'kind = "exec", until_stopped = "yes"'),
     "[modules.m] services.Go: until_stopped = 'yes'; it is true or false"),
    (GOOD.replace('kind = "init"', 'kind = "init", until_stopped = true'),
     "until_stopped = True; it is true or false, and only an exec service may run until stopped"),
])
def test_malformed_interface_names_file_entry_and_value(tmp_path, text, message):
    path = write(tmp_path, "iface.toml", text)
    with pytest.raises(InputFileError) as e:
        load_interface(path)
    assert str(path) in str(e.value) and message in str(e.value)


PROP = '[[property]]\nid = "P"\nfamily = "F"\ntype = "PC"\nx = ["m.Go"]\nq = ["m.Init"]\nr_p = "wait_init"\n'


@pytest.mark.parametrize("text, message", [
    (PROP.replace('"PC"', '"XX"'), "property #1 (P): type 'XX' is not one of EE, ES, EX, MX_I, MX_R, PC "
     "(the templates of sql/oracles/)"),
    (PROP.replace('q = ["m.Init"]\n', ""), "type PC needs 'q', which is missing"),
    (PROP.replace('["m.Go"]', '["m.Fly"]'), "x names 'm.Fly', which the interface"),
    (PROP.replace('"wait_init"', '"interrupted"'), "r_p = 'interrupted' is not a class-R reply code"),
    (PROP + 'y = ["m.Go"]\n', "key(s) ['y'] do not apply to type PC"),
    (PROP + PROP, "property #2 (P): id 'P' is used twice"),
])
def test_malformed_properties_name_file_entry_and_value(tmp_path, text, message):
    iface = load_interface(write(tmp_path, "iface.toml", GOOD))
    path = write(tmp_path, "props.toml", text)
    with pytest.raises(InputFileError) as e:
        load_properties(path, iface)
    assert str(path) in str(e.value) and message in str(e.value)
