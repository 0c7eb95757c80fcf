"""The packages read as the pipeline: the import contract in pyproject.toml holds, and it can fail."""
import subprocess
import sys
from pathlib import Path

from harness import ROOT

LINT = Path(sys.executable).parent / "lint-imports"


def lint(config: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT), "--config", str(config), "--no-cache"], cwd=ROOT,
                          capture_output=True, text=True)


def test_the_layers_contract_is_kept():
    result = lint(ROOT / "pyproject.toml")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 kept, 0 broken" in result.stdout


def test_the_contract_fails_on_an_upward_import(tmp_path):
    # The same contract with report placed below store: report imports the store, so it is broken.
    text = (ROOT / "pyproject.toml").read_text()
    swapped = text.replace('    "harness.report",\n', "").replace('    "harness.store",\n',
                                                                     '    "harness.store",\n    "harness.report",\n')
    assert swapped != text
    config = tmp_path / "pyproject.toml"
    config.write_text(swapped)
    result = lint(config)
    assert result.returncode != 0
    assert "BROKEN" in result.stdout
