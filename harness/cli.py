"""`python -m harness COMMAND`: the bench's command line (docs/reference/commands.md)."""
from __future__ import annotations

import argparse
import gc
import os
import sys
import traceback
from pathlib import Path

from harness import __version__
from harness.sut.roscommon.recording import ROSBAG_ENV
from harness.commands import COMMANDS
from harness.commands.options import typed
from harness.errors import UntimelyError
from harness.sut import processes
from harness.store.database import discard_if_empty


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="untimely",
        description="Untimely: mutate a mission script, run it against a robot's functional layer - the "
                    "bench's simulated layer, an external system under test over the untimely/1 protocol "
                    "(any process or TCP server: --sut NAME=cmd:COMMAND or NAME=tcp://HOST:PORT), or ROS 1 "
                    "actionlib servers through the bundled adapter (docs/ros.md) - store every request and "
                    "reply in DuckDB, judge the traces with SQL oracles.")
    p.add_argument("--version", action="version", version=f"untimely {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        c = sub.add_parser(command.NAME, help=command.HELP, description=command.HELP)
        command.arguments(c)
        c.set_defaults(handler=command)
    return p


def main(argv: list[str] | None = None) -> int:
    try:
        args = _parser().parse_args(argv)
    except SystemExit as e:  # argparse has printed the usage and what is wrong with a flag (or the help)
        return e.code
    for name, value in vars(args).items():
        if isinstance(value, str) and _not_utf8(value):
            print(f"error: --{name.replace('_', '-')} {value!r}: not UTF-8 (the store and its files keep UTF-8 "
                  "names); rename the file or folder", file=sys.stderr)
            return 2
    processes.stop_on_signals()  # SIGTERM and SIGHUP clean up as Ctrl-C does
    processes.become_subreaper()  # daemons detached by adapters come back to be ended
    new_store = None if getattr(args, "db", None) in (None, ":memory:") or Path(args.db).exists() else args.db
    status = _run(args)
    if status and new_store:  # e.g. --sut nonexistent: leave no empty store behind
        gc.collect()  # the failed command's connection, held by its traceback until now
        discard_if_empty(new_store)
    return status


def entry() -> None:
    """The `untimely` command of an installed bench (pyproject.toml's [project.scripts])."""
    sys.exit(main())


CRASHED = 3  # the exit status of an unexpected error (a bug)
DUCKDB_INTERRUPTED = "Query interrupt"  # how DuckDB's RuntimeError begins when Ctrl-C stops one of its queries


def _stopped(how: str = "Ctrl-C", signum: int = 2) -> int:
    print(f"stopped ({how}); the store keeps every finished transaction", file=sys.stderr)
    return 128 + signum


def _interrupted(stop: KeyboardInterrupt) -> int:
    return _stopped(stop.args[0], stop.signum) if isinstance(stop, processes.Stopped) else _stopped()


def _crashed_unless_stopped(command: str) -> int:
    """An error raised after a stop signal came is what the stop became (DuckDB makes a Ctrl-C
    during a replacement scan a CatalogException): the stop, not a bug."""
    stop = processes.stop_under_way()
    return _interrupted(stop) if stop else _crashed(command)


def _crashed(command: str) -> int:
    """A bug: its own status, so that a CI gate never takes it for a finding (status 1)."""
    traceback.print_exc()
    print(f"error: untimely {command} crashed (a bug, not a finding); please report the traceback above",
          file=sys.stderr)
    return CRASHED


def _not_utf8(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:  # bytes of another encoding, which Python keeps as lone surrogates
        return True
    return False


def _run(args) -> int:
    if getattr(args, "rosbag", None):  # the ROS launcher reads it from the environment it inherits
        Path(args.rosbag).mkdir(parents=True, exist_ok=True)
        os.environ[ROSBAG_ENV] = str(Path(args.rosbag).resolve())
    try:
        return args.handler.execute(typed(args.handler.Request, args)) or 0
    except UntimelyError as e:
        stop = processes.stop_under_way()  # e.g. a write the stop cut short, which the store calls a write problem
        if stop:
            return _interrupted(stop)
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as e:
        return _interrupted(e)
    except RuntimeError as e:
        return _stopped() if str(e).startswith(DUCKDB_INTERRUPTED) else _crashed_unless_stopped(args.command)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except Exception:
        return _crashed_unless_stopped(args.command)
    finally:
        os.environ.pop(ROSBAG_ENV, None)
