"""`untimely init DIR [--from-genom FILE.gen]`: a target folder whose golden run completes against
its own adapter and whose campaign runs (keeping the adapter between runs); the refusals, and
init on a place it cannot write (nothing half-written is left) or through a link."""
import errno
import os
from pathlib import Path

import pytest

from harness import store
from harness.cli import main
from harness.target.mission import load_mission


@pytest.mark.slow
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


def test_an_existing_target_is_never_overwritten(tmp_path, capsys):
    assert main(["init", str(tmp_path)]) == 0
    before = (tmp_path / "golden.mission").read_text()
    assert main(["init", str(tmp_path)]) == 2
    assert "already holds interface.toml, properties.toml, golden.mission, standin.toml, suts.toml, adapter.py" in \
        capsys.readouterr().err
    assert (tmp_path / "golden.mission").read_text() == before


@pytest.mark.parametrize("text, message", [
    (None, "no such file; give a GenoM3 .gen file"),
    ("/* nothing */ struct s { long a; };", "no `component NAME { ... };` found"),
    ("component c { version \"1\";", "the file ends inside a declaration"),
    ("component c { version \"1\"; };", "component c states no property untimely can judge"),
])
def test_a_gen_file_that_cannot_be_read_is_refused_naming_it(tmp_path, capsys, text, message):
    gen = tmp_path / "bad.gen"
    if text is not None:
        gen.write_text(text)
    assert main(["init", str(tmp_path / "t"), "--from-genom", str(gen)]) == 2
    err = capsys.readouterr().err
    assert message in err and (text is None or str(gen) in err)
    assert not (tmp_path / "t").exists()


@pytest.mark.parametrize("extra, message", [
    (["--include", "."], "--include is for the #include lines of --from-genom FILE.gen"),
    (["--from-genom", "GEN", "--include", "no/such/folder"], "--include 'no/such/folder': no such folder"),
])
def test_include_folders_are_checked(tmp_path, capsys, extra, message):
    gen = tmp_path / "c.gen"
    gen.write_text("component c { activity A(); };")
    assert main(["init", str(tmp_path / "t"), *[str(gen) if a == "GEN" else a for a in extra]]) == 2
    assert message in capsys.readouterr().err and not (tmp_path / "t").exists()


@pytest.mark.parametrize("error", [errno.ENOSPC, errno.EROFS])
def test_a_full_disk_or_a_read_only_place_leaves_nothing_half_written(tmp_path, capsys, monkeypatch, error):
    """The third file fails to be written: init says why, leaves none of its files, and a second
    init (once there is room) writes the whole target."""
    written = []
    real = Path.write_text

    def failing(self, text, *args, **kwargs):
        written.append(self.name)
        if len(written) == 3:
            raise OSError(error, os.strerror(error))
        return real(self, text, *args, **kwargs)
    monkeypatch.setattr(Path, "write_text", failing)
    folder = tmp_path / "robot"
    assert main(["init", str(folder)]) == 2
    assert f"cannot write the target {folder}/: {os.strerror(error)}; nothing was written" in capsys.readouterr().err
    assert sorted(p.name for p in folder.iterdir()) == []
    monkeypatch.undo()
    assert main(["init", str(folder)]) == 0
    assert load_mission(folder).properties()


def test_init_never_writes_through_a_dangling_link(tmp_path, capsys):
    folder, outside = tmp_path / "robot", tmp_path / "elsewhere" / "golden.mission"
    folder.mkdir()
    (folder / "golden.mission").symlink_to(outside)
    assert main(["init", str(folder)]) == 2
    err = capsys.readouterr().err
    assert f"golden.mission (a link to {outside})" in err and "never through a link" in err
    assert not outside.parent.exists() and [p.name for p in folder.iterdir()] == ["golden.mission"]
