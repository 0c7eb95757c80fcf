"""The bench as a tool people install: the built wheel, installed into a fresh virtual environment
outside the checkout, runs `untimely init robot`, a campaign of the scaffold against its adapter,
`analyze --junit` and `report` from an empty folder; pyproject.toml lists every package; the
README and docs/ refer to nothing outside the repository.

The fresh environment borrows the third-party dependencies (DuckDB, pyarrow, ...) of .venv through
a path file rather than downloading them again: the wheel is installed with --no-deps, and the test
checks that `harness` and its data are imported from the new environment, never from the checkout.
"""
import os
import re
import subprocess
import sys
import sysconfig
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import xmlschema

from harness import ROOT
from tests.support.paths import JUNIT

SCHEMA = JUNIT / "junit.xsd"


def _run(argv, cwd, env=None, timeout=300):
    done = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, f"{argv} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done.stdout


def _packages(folder: Path, name: str) -> set[str]:
    """The package names of a folder and its subfolders, installed as `name`."""
    return {".".join((name, *p.relative_to(folder).parts)) for p in [folder, *folder.rglob("*")]
            if p.is_dir() and "__pycache__" not in p.parts}


def test_pyproject_lists_every_package_and_data_folder():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = (_packages(ROOT / "harness", "harness") | _packages(ROOT / "sql", "harness.sql")
             | _packages(ROOT / "missions", "harness.missions"))
    assert listed == found, f"missing: {sorted(found - listed)}; not there: {sorted(listed - found)}"


def test_nothing_in_the_readme_docs_or_code_refers_outside_the_repository():
    """The product stands alone: no path into the steering folder, no section of a design text it does not ship."""
    files = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    files += [f for folder in ("harness", "sql", "tests", "bench") for f in sorted((ROOT / folder).rglob("*"))
              if f.suffix in (".py", ".sql", ".j2", ".trace", ".toml")]
    outside = [f"{f.relative_to(ROOT)}:{n}: {line.strip()}" for f in files
               for n, line in enumerate(f.read_text().splitlines(), 1) if re.search(r"\.\./shared|DESIGN \u00a7", line)]
    assert not outside, "\n".join(outside)


def test_the_wheel_installed_elsewhere_runs_a_target_from_an_empty_folder(tmp_path):
    dist, env_dir, work = tmp_path / "dist", tmp_path / "env", tmp_path / "work"
    _run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation", "-w", str(dist),
          str(ROOT)], cwd=tmp_path)
    wheel = next(dist.glob("untimely-*.whl"))
    _run([sys.executable, "-m", "venv", "--without-pip", str(env_dir)], cwd=tmp_path)
    python = env_dir / "bin" / "python"
    site = Path(subprocess.check_output([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                                        text=True).strip())
    (site / "borrowed_dependencies.pth").write_text(sysconfig.get_path("purelib") + "\n")
    _run([sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet", "--no-deps", str(wheel)],
         cwd=tmp_path)
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PATH"] = f"{env_dir / 'bin'}{os.pathsep}{env['PATH']}"
    where = _run([str(python), "-c", "import harness; print(harness.__file__, harness.SQL_DIR, harness.__version__)"],
                 cwd=work, env=env)
    assert where.startswith(str(site)) and str(ROOT) not in where, where
    untimely = str(env_dir / "bin" / "untimely")
    assert _run([untimely, "--version"], cwd=work, env=env).strip().startswith("untimely ")
    _run([untimely, "init", "robot"], cwd=work, env=env)
    _run([untimely, "campaign", "--mission", "robot", "--sut", "adapter", "--mutants", "4"], cwd=work, env=env)
    assert (work / "reports" / "campaign.duckdb").exists(), "the default store is under the current folder"
    _run([untimely, "analyze", "--junit", "junit.xml"], cwd=work, env=env)
    xmlschema.XMLSchema(SCHEMA).validate(str(work / "junit.xml"))
    assert len(ET.parse(work / "junit.xml").getroot().findall("testsuite/testcase")) == 6  # outcome + 5 properties
    _run([untimely, "report"], cwd=work, env=env)
    assert (work / "reports" / "index.html").exists()
    _run([str(python), "-m", "harness", "sql", "select untimely from schema_version"], cwd=work, env=env)


def test_make_system_names_the_command_when_it_cannot_install(tmp_path):
    """Not root, packages missing: `make system` stops and names the apt-get command (fake dpkg and id)."""
    for name, script in (("dpkg", "exit 1"), ("id", "echo 1000")):
        (tmp_path / name).write_text(f"#!/bin/sh\n{script}\n")
        (tmp_path / name).chmod(0o755)
    env = dict(os.environ, PATH=f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    done = subprocess.run(["make", "--no-print-directory", "system"], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=60)
    assert done.returncode != 0
    assert "sudo apt-get install -y --no-install-recommends chromium nodejs python3-venv python3-rospy" in done.stdout


def test_the_ci_examples_use_only_commands_and_options_that_exist():
    """Every `untimely` line of docs/ci.md's workflows parses (placeholders filled in); the YAML is
    run by CI servers, the commands themselves by the tests of each command."""
    from harness.cli import _parser
    text = (ROOT / "docs" / "ci.md").read_text()
    lines = [re.sub(r"^.*?\buntimely ", "", line).strip() for line in text.splitlines()
             if re.search(r"(run: |- |^)untimely ", line.strip())]
    assert len(lines) >= 10, lines
    for line in lines:
        filled = re.sub(r"\$\{\{ matrix\.shard \}\}|\$\{CI_NODE_INDEX\}", "1", line)
        filled = filled.replace("${CI_NODE_TOTAL}", "4")
        args = _parser().parse_args(filled.split())
        if getattr(args, "shard", None):
            assert re.fullmatch(r"\d+/\d+", args.shard), line


def test_every_store_records_the_version_of_untimely_that_wrote_it(tmp_path, monkeypatch, capsys):
    from harness import __version__, cli, store
    from harness.store import database
    db = tmp_path / "s.duckdb"
    store.connect(db).close()
    store.connect(db).close()  # the same version again: nothing new to record
    monkeypatch.setattr(database, "__version__", "9.9.9")
    store.connect(db).close()
    con = store.connect(db, read_only=True)
    rows = con.execute("select note, untimely from schema_version order by applied_at").fetchall()
    con.close()
    assert rows == [("created", __version__), ("written by Untimely 9.9.9", "9.9.9")]
    assert cli.main(["--version"]) == 0  # argparse's exit, returned by main
    assert capsys.readouterr().out.strip() == f"untimely {__version__}"
