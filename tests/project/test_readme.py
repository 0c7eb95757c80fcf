"""The README's commands use make or what it installs in .venv, and every `harness` (or `untimely`)
command in it parses (the whole list is run on a fresh clone by .ci/readme_commands.py in CI)."""
import importlib.util
import shlex

import pytest

from harness import ROOT
from harness.cli import _parser

_spec = importlib.util.spec_from_file_location("readme_commands", ROOT / ".ci" / "readme_commands.py")
readme_commands = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(readme_commands)
COMMANDS = readme_commands.commands((ROOT / "README.md").read_text())


def test_the_readme_shows_every_subcommand_through_the_venv_or_make():
    assert COMMANDS, "no command found in the README's ``` blocks"
    for command in COMMANDS:
        assert command.startswith(("make ", ".venv/bin/")), \
            f"{command!r} needs a Python or a tool a fresh clone does not have; use .venv/bin/... or make"
    shown = {shlex.split(c, comments=True)[3] for c in COMMANDS if c.startswith(".venv/bin/python -m harness ")}
    assert {"run", "campaign", "import", "analyze", "report", "sql"} <= shown


BENCH = (".venv/bin/python -m harness ", ".venv/bin/untimely ")


def _argv(command: str) -> list[str]:
    words = shlex.split(command, comments=True)
    return words[3:] if command.startswith(BENCH[0]) else words[1:]


# Folders an `init` command of the README writes before later commands use them.
INITIALISED = [_parser().parse_args(_argv(c)).dir for c in COMMANDS
               if c.startswith(BENCH) and _argv(c)[:1] == ["init"]]


@pytest.mark.parametrize("command", [c for c in COMMANDS if c.startswith(BENCH) and "--version" not in c])
def test_each_harness_command_of_the_readme_parses_and_names_existing_files(command):
    args = _parser().parse_args(_argv(command))
    for name in ("mission", "file", "interface"):
        path = getattr(args, name, None)
        if path and not any(path.startswith(folder + "/") or path == folder for folder in INITIALISED):
            assert (ROOT / path).exists(), f"{command!r} names a file the clone lacks"


def test_template_blocks_are_not_run_and_other_blocks_are():
    text = "```\nmake venv\n# a comment\n```\nprose\n```text\n./my-adapter --robot dala\n```\n```sh\nmake report\n```\n"
    assert readme_commands.commands(text) == ["make venv", "make report"]
    assert not [c for c in COMMANDS if "my-adapter" in c or "7400" in c]
