"""layer.toml: what a simulated layer enforces, read once and checked against the interface;
a bad entry is refused naming the file, the entry and the bad value."""
import shutil

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.campaign.config import campaign_config
from harness.campaign.request import CampaignRequest
from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.target.mission import load_mission
from harness.target.mission import load_layer
from harness.sut.simulated.kernel import Environment
from harness.sut.simulated.layer import FunctionalLayer


def test_dalas_variants_and_their_protections_in_checking_order():
    layer = load_layer(DEFAULT_MISSION_DIR)
    assert list(layer.variants) == ["genom", "bip-a", "bip-b", "bare", "reference"]
    assert [p.name for p in layer.variant("bip-b").protections] == ["RANGE", "PEX", "AIB", "PRE", "EXC"]
    assert layer.variant("genom").protections[0].checks == ("range",)
    assert layer.variant("bare").protections == ()
    assert layer.default_suts == ("genom", "bip-a", "bip-b")
    assert load_mission(DEFAULT_MISSION_DIR).default_suts() == "genom,bip-a,bip-b"


@pytest.fixture
def folder(tmp_path):
    copy = tmp_path / "dala"
    shutil.copytree(DEFAULT_MISSION_DIR, copy)
    return copy


@pytest.mark.parametrize("old,new,message", [
    ('kind = "excludes"', 'kind = "forbids"', r"layer.toml:\d+: protections.EXC.kind = 'forbids'; use one of "
                                              r"checks_args, narrows_while, requires_init, requires, rejects_while, "
                                              r"interrupts, excludes"),
    ('protections = ["RANGE", "PEX", "AIB"]\n', 'protections = ["PEX", "AIB", "XYZ"]\n',
     r"layer.toml:\d+: variants.genom.protections names 'XYZ'; use one of VAL, RANGE, PEX, AIB, PRE, EXC"),
    ('checks = ["range"]', 'checks = ["size"]',
     r"layer.toml:\d+: protections.RANGE.checks\[1\] = 'size'; give 'missing', 'type', 'nan', 'range'"),
    ('protection = "AIB"', 'protection = "ZZZ"', r"layer.toml:\d+: defects.deadlock_on_dominated_start: "
                                                 r"protection = 'ZZZ'; name one of VAL, RANGE, PEX"),
    ('default_suts = ["genom", "bip-a", "bip-b"]', 'default_suts = ["genom", "bip-z"]',
     r"layer.toml:12: layer.default_suts names 'bip-z'; use one of genom, bip-a"),
    ('slots = 3 ', 'slots = 0 ', r"layer.toml:8: layer.slots = 0; give a whole number of activities >= 1"),
    ('Stop = { start_s = 0.01, run_s = 0.05 }', 'Stop = { start_s = 0.01, run_s = "long" }',
     r"layer.toml:17: timing.Stop.run_s = 'long'; give a number of seconds >= 0 or \"forever\""),
    ('[layer]\n', '[layer]\ncolour = "red"\n', r"layer.toml:6: unknown key 'colour'; \[layer\] takes doc, behaviour"),
    # negative durations (every run would crash), a module that is no behaviour, wrong TOML types
    ('Stop = { start_s = 0.01, run_s = 0.05 }', 'Stop = { start_s = 0.01, run_s = -0.05 }',
     r"layer.toml:17: timing.Stop: run_s = -0.05; give a number of seconds >= 0"),
    ('Stop = { start_s = 0.01, run_s = 0.05 }', 'Stop = { start_s = -1, run_s = 0.05 }',
     r"layer.toml:17: timing.Stop.start_s = -1; give a number of seconds >= 0"),
    ('slots = 3 ', 'slots = 3.5 ', r"layer.toml:8: layer.slots = 3.5; give a whole number of activities >= 1"),
    ('slots = 3 ', 'slots = true ', r"layer.toml:8: layer.slots = True; give a whole number"),
    ('pairs = [', 'pairs = 7\nold_pairs = [', r"layer.toml:\d+: protections.EXC.pairs = 7; give a list of"),
    ('reply = "interrupted_excl"', 'reply = ["interrupted_excl"]',
     r"layer.toml:\d+: protections.EXC.reply = \['interrupted_excl'\]; give the reply code it answers with"),
])
def test_a_bad_entry_is_refused_naming_it(folder, old, new, message):
    path = folder / "layer.toml"
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(UntimelyError, match=message):
        load_layer(folder)


@pytest.mark.parametrize("name, message", [
    ("os", r"layer.toml:7: behaviour = 'os' has no build\(env, world_file\) function; name a module that builds"),
    ("no.such.module", r"layer.toml:7: behaviour = 'no.such.module' cannot be imported \(No module named 'no'\); "
                       r"name an importable"),
])
def test_a_behaviour_module_that_builds_nothing_is_refused_before_any_run(folder, tmp_path, name, message):
    path = folder / "layer.toml"
    path.write_text(path.read_text().replace('"harness.sut.dala.behaviour"', f'"{name}"'))
    with pytest.raises(UntimelyError, match=message):
        load_layer(folder).behaviour_module()
    with pytest.raises(UntimelyError, match=message):  # a campaign checks it before it runs anything
        mission = load_mission(folder)
        campaign_config(CampaignRequest(mission=str(folder), mutants=1, jobs=1, max_delay=0.0, seed=1), mission,
                        mission.golden())


def test_codes_and_services_must_be_the_interfaces(folder):
    path = folder / "layer.toml"
    path.write_text(path.read_text().replace('reply = "disallowed"', 'reply = "nope"'))
    interface = load_interface(folder / "interface.toml")
    with pytest.raises(UntimelyError, match=r"layer.toml: reply code 'nope' is not in the catalogue of the "
                                            r"interface .*interface.toml; add it there"):
        FunctionalLayer(Environment(), "reference", interface, folder / "world.toml")
    path.write_text(path.read_text().replace('reply = "nope"', 'reply = "disallowed"')
                    .replace('"ndd.GotoPosition" = ["ndd.SetParams"]', '"ndd.Fly" = ["ndd.SetParams"]'))
    with pytest.raises(UntimelyError, match=r"layer.toml:\[protections.PRE\]: names 'ndd.Fly', which the "
                                            r"interface .* does not declare"):
        FunctionalLayer(Environment(), "reference", interface, folder / "world.toml")


def test_a_folder_without_a_layer_has_no_default_variants(folder):
    (folder / "layer.toml").unlink()
    with pytest.raises(UntimelyError, match=r"layer.toml: file not found; a folder without a simulated layer "
                                            r"needs --sut NAME=cmd:COMMAND"):
        load_mission(folder).default_suts()


def test_a_state_dependent_domain_naming_an_unknown_argument_is_refused(tmp_path):
    copy = tmp_path / "manipulator"
    shutil.copytree(DEFAULT_MISSION_DIR.parent / "manipulator", copy)
    path = copy / "layer.toml"
    path.write_text(path.read_text().replace("domain = { speed = { max = 0.3 } }", "domain = { sped = { max = 0.3 } }"))
    mission = load_mission(copy)
    with pytest.raises(UntimelyError, match=r"layer.toml:\[protections.SLOW\]: domain names argument 'sped', "
                                            r"which none of its services takes; they take speed"):
        FunctionalLayer(Environment(), "safe", mission.interface, copy / "world.toml")
