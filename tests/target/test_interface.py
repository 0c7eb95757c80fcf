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


def test_dala_interface_and_25_properties(interface, properties):
    assert interface.modules == ["rflex", "sick", "aspect", "ndd", "antenna"]
    assert interface.services["ndd.GotoPosition"].kind == "exec"
    assert interface.replies["interrupted_excl"] == "Z"
    assert len(properties) == 25
    families = {}
    for p in properties:
        families[p.family] = families.get(p.family, 0) + 1
    assert families == {"PEX": 5, "AIB": 7, "PRE": 6, "EXC": 3, "VAL": 4}
    assert {p.type for p in properties} == {"PC", "EE", "MX_I", "VAL"}
    assert interface.until_stopped == ["rflex.TrackSpeedStart", "sick.ContinuousShot", "aspect.Fuse"]
    assert interface.of_kind("control") == ["rflex.SetMode", "sick.SetParams", "ndd.SetParams", "antenna.SetChannel"]


@pytest.mark.parametrize("text, message", [
    (GOOD.replace('interrupted = "Z"', 'interrupted = "X"'), ":4: replies.interrupted = 'X'; give 'T', 'Z' or 'R'"),
    (GOOD.replace('kind = "exec"', 'kind = "run"'), ":8: modules.m.services.Go.kind = 'run'; give one of init, control, exec"),
    (GOOD.replace("max = 1.0", "max = -1.0"), ":8: modules.m.services.Go.args.v: needs min <= max, got min=0.0 max=-1.0"),
    (GOOD.replace('ok = "T"', ""), "iface.toml: the reply catalogue must contain ok"),
    (GOOD.replace('ok = "T"', 'ok = "R"'), "the reply catalogue must contain ok = \"T\", not ok = 'R'"),
    (GOOD.replace('kind = "exec", args', 'kind = "exec", agrs'),
     ":8: unknown key 'agrs'; a service takes kind, args, until_stopped, doc"),
    (GOOD.replace("[modules.m]", "[modules.m]\nposter = \"P\"\nposters = \"Q\""),
     ":8: unknown key 'posters'; a module takes doc, poster, services"),
    (GOOD.replace("max = 1.0", "max = 1.0, choices = [\"a\"]"),
     ":8: unknown key 'choices'; a float argument takes type, min, max, required, doc"),
    (GOOD + "[reply]\nok = \"T\"\n", ":9: unknown key 'reply'; the top level takes replies, modules"),
    (GOOD.replace("max = 1.0", "max = 1.0, required = \"yes\""), ":8: modules.m.services.Go.args.v.required = 'yes'; "
                                                              "give true or false"),
    (GOOD.replace("max = 1.0", "max = inf"), ":8: modules.m.services.Go.args.v.max = inf; give a finite number"),
    (GOOD.replace('type = "float", min = 0.0, max = 1.0', 'type = "str", pattern = "[a-z"'),
     ":8: modules.m.services.Go.args.v: pattern = '[a-z' is not a regular expression"),
    (GOOD.replace('type = "float", min = 0.0, max = 1.0', 'type = "str", choices = "a"'),
     ":8: modules.m.services.Go.args.v.choices = 'a'; give a list of string choices"),
    ("[replies\n", "not valid TOML"),
    (GOOD.replace('kind = "exec"', 'kind = "exec", until_stopped = "yes"'),
     ":8: modules.m.services.Go.until_stopped = 'yes'; give true or false"),
    (GOOD.replace('kind = "init"', 'kind = "init", until_stopped = true'),
     ":7: modules.m.services.Init: until_stopped = true on an init service; only an exec service may run until stopped"),
    # wrong TOML types, NaN, a value too long to echo, an unknown argument type
    (GOOD.replace("[modules.m]", "[modules]\nrflex = 5\n[modules.m]"), ":7: modules.rflex = 5; give a table"),
    (GOOD.replace('services.Init = { kind = "init" }\nservices.Go', 'services = ["Init"]\nservices2.Go'),
     ":7: modules.m.services = ['Init']; declare the module's services: services.NAME = { kind = .. }"),
    (GOOD.replace('args = { v = { type = "float", min = 0.0, max = 1.0 } }', 'args = ["v"]'),
     ":8: modules.m.services.Go.args = ['v']; give a table of name = { type = .. }"),
    (GOOD.replace("min = 0.0", "min = nan"), ":8: modules.m.services.Go.args.v.min = nan; give a finite number"),
    (GOOD.replace('kind = "exec"', 'kind = "' + "x" * 1_000_000 + '"'),
     "... (1,000,002 characters); give one of init, control, exec"),
    (GOOD.replace('type = "float"', 'type = "int"'), "modules.m.services.Go.args.v = {'type': 'int', 'min': 0.0, "
                                                     "'max': 1.0}; give 'type' = 'float', 'str'"),
])
def test_malformed_interface_names_file_entry_and_value(tmp_path, text, message):
    path = write(tmp_path, "iface.toml", text)
    with pytest.raises(InputFileError) as e:
        load_interface(path)
    assert str(path) in str(e.value) and message in str(e.value) and len(str(e.value)) < 400


PROP = '[[property]]\nid = "P"\nfamily = "F"\ntype = "PC"\nx = ["m.Go"]\nq = ["m.Init"]\nr_p = "wait_init"\n'
VAL = '[[property]]\nid = "V"\nfamily = "VAL"\ntype = "VAL"\nx = ["m.Go"]\n'


@pytest.mark.parametrize("text, message", [
    (PROP.replace('"PC"', '"XX"'), ":1: property[1]: type 'XX' is not one of CAN, EE, ES, EX, GOAL, IN, MX_I, MX_R, OUT, OUTLIVE, PC, RSP, VAL (the templates of sql/oracles/)"),
    (PROP.replace('q = ["m.Init"]\n', ""), ":1: property[1]: type PC needs 'q', which is missing"),
    (PROP.replace('["m.Go"]', '["m.Fly"]'), ":5: property 'P': x names 'm.Fly', which the interface"),
    (PROP.replace('"wait_init"', '"interrupted"'), ":7: property 'P': r_p = 'interrupted' is not a class-R reply code"),
    (PROP + 'y = ["m.Go"]\n', ":1: property[1]: key(s) ['y'] do not apply to type PC"),
    (PROP + PROP, ":8: property id 'P' is used twice (also property #1)"),
    ("property = [1, 2]\n", ":1: property[1] = 1; give a table"),
    (PROP.replace('"wait_init"', '["wait_init"]'), ":7: property[1].r_p = ['wait_init']; give the rejection code"),
    ("", "props.toml: property is missing; add [[property]] entries"),
    (VAL + 'y = ["m.Init"]\n', ":1: property[1]: a state-dependent VAL property needs both y (the activities during "
                                "which it holds) and domain (what it allows then); give both or neither"),
    (VAL + 'y = ["m.Init"]\ndomain = { w = { max = 0.5 } }\n',
     ":7: property 'V': domain names argument 'w', which none of its services takes; they take v"),
    (VAL + 'y = ["m.Init"]\ndomain = { v = { most = 0.5 } }\n',
     ":7: unknown key 'most'; a narrowed domain takes min, max, choices, pattern"),
    (VAL + 'y = ["m.Init"]\ndomain = { v = { choices = ["a"] } }\n',
     ":7: property 'V': domain.v sets choices, which do not apply to a float argument"),
    (VAL + 'r_p = "interrupted"\n', "property 'V': r_p = 'interrupted' is not a class-R reply code"),
])
def test_malformed_properties_name_file_entry_and_value(tmp_path, text, message):
    iface = load_interface(write(tmp_path, "iface.toml", GOOD))
    path = write(tmp_path, "props.toml", text)
    with pytest.raises(InputFileError) as e:
        load_properties(path, iface)
    assert str(path) in str(e.value) and message in str(e.value)


def test_a_domain_defaults_to_any_value_of_its_type(tmp_path):
    text = GOOD.replace("min = 0.0, max = 1.0", "required = false") + \
        'services.Say = { kind = "control", args = { w = { type = "str" } } }\n'
    services = load_interface(write(tmp_path, "iface.toml", text)).services
    v, w = services["m.Go"].args["v"], services["m.Say"].args["w"]
    assert (v.min, v.max, v.required, w.choices, w.pattern, w.required) == (None, None, False, (), None, True)
    assert (v.describe(), w.describe()) == ("optional float", "str")
    assert services["m.Go"].typed({"v": "-1e6"}) == {"v": -1e6}
    assert services["m.Say"].typed({"w": '""'}) == {"w": ""}


def test_the_keys_a_table_accepts_are_those_its_refusal_lists(tmp_path):
    """INTERFACE_KEYS (which docs/reference is checked against) comes from the schema models."""
    from harness.target.interface import INTERFACE_KEYS
    path = write(tmp_path, "iface.toml", GOOD.replace('kind = "exec", args', 'kind = "exec", agrs'))
    with pytest.raises(InputFileError) as e:
        load_interface(path)
    assert str(e.value).endswith(f"a service takes {', '.join(INTERFACE_KEYS['a service'])}")
    assert INTERFACE_KEYS["a service"] == ("kind", "args", "until_stopped", "doc")
