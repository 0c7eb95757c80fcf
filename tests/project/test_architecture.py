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
    assert "3 kept, 0 broken" in result.stdout


def lint_changed(tmp_path, *replacements: tuple[str, str]) -> subprocess.CompletedProcess:
    """lint-imports on pyproject.toml with each (old, new) of `replacements` made."""
    text = changed = (ROOT / "pyproject.toml").read_text()
    for old, new in replacements:
        changed = changed.replace(old, new)
    assert changed != text
    config = tmp_path / "pyproject.toml"
    config.write_text(changed)
    return lint(config)


def test_the_contract_fails_on_an_upward_import(tmp_path):
    # The same contract with report placed below store: report imports the store, so it is broken.
    result = lint_changed(tmp_path, ('    "harness.report",\n', ""),
                          ('    "harness.store",\n', '    "harness.store",\n    "harness.report",\n'))
    assert result.returncode != 0
    assert "BROKEN" in result.stdout


def test_the_store_contract_fails_on_a_package_that_imports_a_sut(tmp_path):
    # The same contract with campaign in the store's place: campaign imports harness.sut, so it is broken.
    result = lint_changed(tmp_path, ('source_modules = ["harness.store"]', 'source_modules = ["harness.campaign"]'))
    assert result.returncode != 0
    assert "the store knows no SUT BROKEN" in result.stdout
