"""The command layer (harness/commands/): each command a module the import contract sees, the
parser making a typed request whose defaults are the dataclass's, a `--help` that says what each
command and flag is for, and argparse nowhere below the layer but in programs of their own."""
import ast
import dataclasses
import re

import grimp
import pytest

from harness import ROOT
from harness.campaign.request import CampaignRequest, RunRequest, ShrinkRequest
from harness.cli import _parser, main
from harness.commands import COMMANDS
from harness.commands.options import MAX_JOBS, typed

# The positional arguments each command needs, and the typed request they make with every default.
MINIMAL = {"run": ["m.mission", "--sut", "genom"], "merge": ["out.duckdb", "a.duckdb"], "init": ["dir"],
           "shrink": ["7"], "explain": ["7", "P1"], "import": ["t.csv", "--interface", "i.toml"],
           "export": ["dir"], "sql": ["select 1"]}


def _request(argv: list[str]):
    args = _parser().parse_args(argv)
    return typed(args.handler.Request, args)


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c.NAME)
def test_the_flags_defaults_are_the_typed_requests_defaults(command):
    request = _request([command.NAME, *MINIMAL.get(command.NAME, [])])
    assert isinstance(request, command.Request)
    required = {f.name: getattr(request, f.name) for f in dataclasses.fields(request)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING}
    assert request == command.Request(**required)


def test_the_parser_checks_and_converts_each_value_into_the_request():
    request = _request(["campaign", "--jobs", "2", "--seed", "-5", "--max-delay", "0.5", "--time-scale", "20",
                        "--cluster", "local:2", "--shrink", "--db", "x.duckdb"])
    assert request == CampaignRequest(jobs=2, seed=-5, max_delay=0.5, time_scale=20.0, cluster="local:2",
                                      shrink=True, db="x.duckdb")
    assert _request(["run", "g.mission", "--sut", "toy=tcp://127.0.0.1:9", "--seed", "3"]) == \
        RunRequest("g.mission", "toy=tcp://127.0.0.1:9", seed=3)
    assert _request(["shrink", "4", "--property", "P", "--verdict", "FP"]) == ShrinkRequest(4, "P", "FP")


@pytest.mark.parametrize("argv, words", [
    (["campaign", "--jobs", "-1"], ["--jobs", "'-1'", f"from 1 to {MAX_JOBS}", "0 for all cores"]),
    (["campaign", "--jobs", str(MAX_JOBS + 1)], ["--jobs", f"'{MAX_JOBS + 1}'"]),
    (["campaign", "--max-delay", "-0.1"], ["--max-delay", "'-0.1'", "seconds >= 0"]),
    (["run", "g.mission", "--sut", "genom", "--time-scale", "0"], ["--time-scale", "'0'", "factor > 0"]),
    (["campaign", "--time-scale", "nan"], ["--time-scale", "'nan'", "factor > 0"]),
    (["analyze", "--epsilon", "inf"], ["--epsilon", "'inf'", "seconds >= 0"]),
])
def test_a_bad_value_is_refused_once_by_the_parser_naming_flag_value_and_remedy(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err
    assert err.count("give") == 1, err


def _help(argv: list[str], capsys) -> str:
    assert main([*argv, "--help"]) == 0
    return " ".join(capsys.readouterr().out.split())


def test_the_help_lists_every_command_with_what_it_does(capsys):
    text = _help([], capsys)
    for command in COMMANDS:
        assert re.search(rf"\b{command.NAME} {re.escape(' '.join(command.HELP.split()[:4]))}", text), command.NAME


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c.NAME)
def test_each_commands_help_says_what_it_and_each_of_its_flags_is_for(command, capsys):
    text = _help([command.NAME], capsys)
    assert " ".join(command.HELP.split()) in text
    for action in _parser()._subparsers._group_actions[0].choices[command.NAME]._actions:
        if action.dest != "help":
            assert action.help and " ".join(action.help.split()[:3]) in text, (command.NAME, action.dest)


def test_the_help_gives_the_defaults_and_the_choices_a_user_needs(capsys):
    text = _help(["campaign"], capsys)
    for words in ("number of mutants (default: 300)", "campaign seed (default: 2012)", "genom, bip-a",
                  f"at most {MAX_JOBS}", "tcp://HOST:8786", "NAME=cmd:COMMAND", "(default: reports/campaign.duckdb)"):
        assert words in text, words
    assert "{random,targeted,focused}" in text
    assert "NAME=tcp://HOST:PORT" in _help(["run"], capsys)


def test_the_import_contract_sees_every_command_reach_its_implementation():
    graph = grimp.build_graph("harness")
    for command in COMMANDS:
        below = {m for m in graph.find_modules_directly_imported_by(command.__name__)
                 if not m.startswith(("harness.commands", "harness.errors")) and m != "harness"}
        assert below, f"{command.__name__} imports no implementation: the contract cannot see what it runs"
    assert not {m for m in graph.find_modules_directly_imported_by("harness.cli") if m.startswith("importlib")}


def test_argparse_below_the_command_layer_only_parses_a_program_of_its_own():
    for path in sorted((ROOT / "harness").rglob("*.py")):
        if path.name == "cli.py" and path.parent.name == "harness" or "commands" in path.parts:
            continue
        tree = ast.parse(path.read_text())
        imported = any(isinstance(n, ast.Import) and any(a.name == "argparse" for a in n.names) for n in ast.walk(tree))
        if imported:
            assert "ArgumentParser(" in path.read_text(), \
                f"{path.relative_to(ROOT)} uses argparse without a parser of its own: pass it a typed request"
