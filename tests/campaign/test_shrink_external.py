"""Shrinking traces of external SUTs: the shipped simulator adapter (sim-genom), and a
standard-library adapter of a target folder outside the repository that its suts.toml names
relative to the folder. A command recorded in a store runs only when the user names it again."""
import re
import shutil

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.cli import main as cli
from tests.support.external import ADAPTER

# genom's init_interrupts defect: an Init interrupts the running TrackSpeedStart (an FP on its AIB).
INIT_INTERRUPTS = """send rflex.Init as ri
wait ri
send sick.Init as si
wait si
send rflex.SetMode mode=velocity as m
wait m
send rflex.TrackSpeedStart as t
sleep 1
send rflex.Init as r2
wait all
"""
EAGER = """send sick.Init as si
wait si
send rflex.TrackSpeedStart as t
wait t
send rflex.Init as ri
wait ri
"""


def target(folder, script: str, suts: str | None = None):
    for name in ("interface.toml", "properties.toml", "world.toml", "layer.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, folder / name)
    (folder / "suts.toml").write_text(suts or (DEFAULT_MISSION_DIR / "suts.toml").read_text())
    (folder / "m.mission").write_text(script)
    return folder / "m.mission"


@pytest.mark.slow
def test_a_trace_of_sim_genom_shrinks_once_its_sut_is_named_again(tmp_path, capsys):
    mission, db = target(tmp_path, INIT_INTERRUPTS), str(tmp_path / "s.duckdb")
    assert cli(["run", str(mission), "--sut", "sim-genom", "--time-scale", "20", "--db", db]) == 0
    capsys.readouterr()
    assert cli(["shrink", "1", "--db", db]) == 2  # the store's command is not run on its word
    assert re.search(r"error: trace 1 ran on 'sim-genom', whose command the store records as '\{python\} -m "
                     r"harness.sut.simulated --variant genom'; shrink does not run a command read from a store: "
                     r"name the SUT again with --sut sim-genom=cmd:COMMAND, or --mission FOLDER",
                     capsys.readouterr().err)
    assert cli(["shrink", "1", "--db", db, "--mission", str(tmp_path), "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    found = re.search(r"FP on AIB\(rflex.TrackSpeedStart\) on sim-genom: trace 1 shrunk from 10 to (\d+) steps", out)
    assert found and int(found.group(1)) < 10, out
    reproducer = next((tmp_path / "out").glob("script-*.mission")).read_text()
    assert "send rflex.TrackSpeedStart" in reproducer and "send rflex.Init" in reproducer


def test_a_stdlib_adapter_outside_the_repository_shrinks(tmp_path, capsys):
    (tmp_path / "adapter.py").write_text(ADAPTER)
    suts = '[yes-man]\ncommand = "{python} adapter.py"\ntime_scale = 10.0\n'  # relative to the folder
    mission, db = target(tmp_path, EAGER, suts), str(tmp_path / "y.duckdb")
    assert cli(["run", str(mission), "--sut", "yes-man", "--db", db]) == 0
    capsys.readouterr()
    assert cli(["shrink", "1", "--db", db, "--sut", "yes-man", "--mission", str(tmp_path),
                "--property", "PEX(rflex)", "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert re.search(r"FN on PEX\(rflex\) on yes-man: trace 1 shrunk from 6 to [12] steps", out), out


def test_a_confirmed_stored_command_runs_and_a_wrong_sut_is_refused(tmp_path, capsys):
    (tmp_path / "adapter.py").write_text(ADAPTER)
    suts = '[yes-man]\ncommand = "{python} adapter.py"\ntime_scale = 10.0\n'
    mission, db = target(tmp_path, EAGER, suts), str(tmp_path / "y.duckdb")
    assert cli(["run", str(mission), "--sut", "yes-man", "--db", db]) == 0
    capsys.readouterr()
    assert cli(["shrink", "1", "--db", db, "--sut", "genom"]) == 2
    assert "error: --sut 'genom' does not name trace 1's SUT 'yes-man'; give --sut yes-man" in capsys.readouterr().err
    # the recorded command starts in the folder it was defined in, as when it was recorded
    assert cli(["shrink", "1", "--db", db, "--run-stored-command", "--property", "PEX(rflex)",
                "--out", str(tmp_path / "out")]) == 0
    assert "FN on PEX(rflex) on yes-man" in capsys.readouterr().out


@pytest.mark.parametrize("command", ['"{python} adapter.py', "'unclosed"])
def test_a_command_with_an_unclosed_quote_is_named(tmp_path, capsys, command):
    mission = target(tmp_path, EAGER, f"[x]\ncommand = '''{command}'''\n")
    assert cli(["run", str(mission), "--sut", "x", "--db", str(tmp_path / "x.duckdb")]) == 2
    assert re.search(r"suts.toml:1: x: command = .*: No closing quotation; close the quote",
                     capsys.readouterr().err)


@pytest.mark.slow
def test_campaign_shrink_on_an_external_sut(tmp_path, capsys):
    (tmp_path / "adapter.py").write_text(ADAPTER)
    suts = '[yes-man]\ncommand = "{python} adapter.py"\ntime_scale = 10.0\n'
    (tmp_path / "golden.mission").write_text(EAGER)
    target(tmp_path, EAGER, suts)
    assert cli(["campaign", "--mission", str(tmp_path), "--sut", "yes-man", "--mutants", "2", "--jobs", "1",
                "--shrink", "--db", str(tmp_path / "c.duckdb")]) == 0
    out = capsys.readouterr().out
    assert re.search(r"FN on PEX\(rflex\) on yes-man: trace \d+ shrunk from \d+ to 1 steps", out), out
