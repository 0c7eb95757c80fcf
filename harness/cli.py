"""`python -m harness COMMAND`: the bench's command line (docs/reference/commands.md)."""
from __future__ import annotations

import argparse
import gc
import importlib
import os
import re
import sys
import traceback
from pathlib import Path

from harness import DEFAULT_DB, DEFAULT_EPSILON_S, DEFAULT_MISSION_DIR, __version__
from harness.sut.ros.recorder import ROSBAG_ENV
from harness.errors import UntimelyError
from harness.sut import processes
from harness.mutator.operators import OPERATORS, REQUEST_OPERATORS
from harness.store.database import discard_if_empty

MAX_JOBS = max(64, 2 * (os.cpu_count() or 1))  # more worker processes only compete for the machine


def _checked(convert, accept, what: str):
    """An argparse type: `convert` the text, refused with `what` to give unless `accept(value)`."""
    def parse(text: str):
        try:
            value = convert(text)
        except (ValueError, OverflowError):
            value = None
        if value is None or not accept(value):  # a NaN is accepted by no comparison
            shown = text if len(text) <= 40 else text[:40] + "..."
            raise argparse.ArgumentTypeError(f"{shown!r}: give {what}")
        return value
    return parse


SEED = _checked(int, lambda v: -2**63 <= v < 2**63, "a whole number from -2^63 to 2^63 - 1 (the store keeps 64 bits)")
SECONDS = _checked(float, lambda v: 0 <= v < float("inf"), "a number of seconds >= 0")
SCALE = _checked(float, lambda v: 0 < v < float("inf"), "a finite factor > 0 (1 = real time)")
JOBS = _checked(int, lambda v: 0 <= v <= MAX_JOBS, f"a number of worker processes from 1 to {MAX_JOBS}, or 0 for "
                                                   "all cores")
COUNT = _checked(int, lambda v: v >= 1, "a whole number >= 1")
CLUSTER = _checked(str, lambda v: re.fullmatch(r"local:[1-9]\d{0,2}|tcp://[^\s:/]+:\d{1,5}", v) is not None,
                   "tcp://HOST:PORT (a Dask scheduler) or local:N with N from 1 to 999 local workers")

EXTERNAL_HELP = ("; or an external SUT over untimely/1: NAME=cmd:COMMAND (started per run, stdio), "
                 "NAME=tcp://HOST:PORT, or a NAME from the mission folder's suts.toml")


def _variants_help() -> str:
    """The default mission's variants, read from its layer description."""
    try:
        from harness.target.layer_description import load_layer
        layer = load_layer(DEFAULT_MISSION_DIR)
    except UntimelyError:
        return "those of the mission folder's layer.toml"
    return f"{', '.join(layer.variants)} (for {DEFAULT_MISSION_DIR.name}; others: the mission folder's layer.toml)"


def _parser() -> argparse.ArgumentParser:
    variants_help = _variants_help()
    p = argparse.ArgumentParser(
        prog="untimely",
        description="Untimely: mutate a mission script, run it against a robot's functional layer - the "
                    "bench's simulated layer, an external system under test over the untimely/1 protocol "
                    "(any process or TCP server: --sut NAME=cmd:COMMAND or NAME=tcp://HOST:PORT), or ROS 1 "
                    "actionlib servers through the bundled adapter (docs/ros.md) - store every request and "
                    "reply in DuckDB, judge the traces with SQL oracles.")
    p.add_argument("--version", action="version", version=f"untimely {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name, help, target):
        c = sub.add_parser(name, help=help, description=help)
        c.set_defaults(target=target)
        return c

    def time_scale(c):
        c.add_argument("--time-scale", type=SCALE, help="external SUTs: mission seconds per wall second "
                       "(1 = real time; default: the SUT's own, else 1)")

    def rosbag(c):
        c.add_argument("--rosbag", metavar="DIR", help="ROS SUTs: record each run's bag as DIR/trace-ID.bag "
                       "with Debian's rosbag (docs/ros.md)")

    def db(c, help="the DuckDB store"):
        c.add_argument("--db", default=str(DEFAULT_DB), help=f"{help} (default: %(default)s)")

    c = command("run", "run one script on one variant, store and summarise its trace", "harness.campaign.adhoc:main")
    c.add_argument("mission", help="a mission script, e.g. missions/dala/golden.mission")
    c.add_argument("--sut", required=True, help=f"implementation variant: {variants_help}{EXTERNAL_HELP}")
    c.add_argument("--seed", type=SEED, default=0, help="seed of the observation delays (default: 0)")
    c.add_argument("--interface", help="interface description (default: interface.toml beside the script)")
    c.add_argument("--world", help="world description (default: world.toml beside the script)")
    c.add_argument("--max-delay", type=SECONDS, default=0.003,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    time_scale(c)
    rosbag(c)
    db(c)

    c = command("campaign", "run golden + seeded mutants on each variant; resumable", "harness.campaign.campaign:main")
    c.add_argument("--mission", default=str(DEFAULT_MISSION_DIR), help="mission folder (default: %(default)s)")
    c.add_argument("--mutants", type=int, default=300, help="number of mutants (default: %(default)s)")
    c.add_argument("--sut", help="comma-separated SUTs (default: the layer.toml's default_suts): "
                   f"variants {variants_help}{EXTERNAL_HELP}")
    c.add_argument("--seed", type=SEED, default=2012, help="campaign seed (default: %(default)s)")
    c.add_argument("--jobs", type=JOBS, default=0, help=f"worker processes, 0 = all cores, at most {MAX_JOBS} "
                                                        "(default: %(default)s)")
    c.add_argument("--strategy", choices=("random", "targeted", "focused"), default="random",
                   help="random: the paper's operators; targeted: mutants aimed at falsifying the "
                        "least-covered properties' conditions; focused: short tests, one per way to "
                        "falsify a condition, until the campaign decides it is done (default: %(default)s)")
    c.add_argument("--budget", metavar="DURATION",
                   help="focused only: the mission time all runs may take, shrink runs included "
                        "(4000s, 40m, 1h; default: none, the stopping rule ends the campaign)")
    c.add_argument("--ops-per-mutant", type=COUNT, default=None,
                   help="mutation operations per mutant (default: 1 random, 3 targeted)")
    c.add_argument("--shrink", action="store_true",
                   help="then shrink one representative trace of each distinct bad behaviour "
                        "(focused: each new finding as it shows, within the budget)")
    c.add_argument("--time-mutations", action="store_true", help="also drop waits and change sleeps")
    c.add_argument("--value-mutations", action="store_true",
                   help="also give arguments exceptional values (bounds, beyond them, nan, wrong types, ...); "
                        "targeted and focused: also aim at the value-domain properties")
    c.add_argument("--operators", metavar="A,B", help="the mutation operators random mutants draw among, of "
                   f"{', '.join(OPERATORS)} (default: the paper's three, {', '.join(REQUEST_OPERATORS)})")
    c.add_argument("--cluster", metavar="ADDRESS", type=CLUSTER, help="run on a Dask cluster: a scheduler address "
                   "(tcp://HOST:8786) or local:N for N local workers; needs the cluster extra (docs/cluster.md)")
    c.add_argument("--max-delay", type=SECONDS, default=0.003,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    c.add_argument("--shard", metavar="I/N", help="run only the I-th of N disjoint parts of the campaign "
                   "(1 <= I <= N) into this store; `merge` combines the N stores (docs/ci.md)")
    c.add_argument("--allow-code-change", action="store_true",
                   help="resume a campaign that another version of the bench's code made (its traces then "
                        "mix runs of both; refused without it)")
    time_scale(c)
    rosbag(c)
    db(c)

    c = command("merge", "combine the stores of a sharded campaign (campaign --shard I/N) into one",
                "harness.campaign.sharding:merge_main")
    c.add_argument("out", help="the merged store, a new file")
    c.add_argument("stores", nargs="+", metavar="STORE", help="the shards' stores, one per part")
    c.add_argument("--properties", help="properties to judge the merged traces with (default: those of the "
                                        "shards' last analysis, else the campaign mission's)")

    c = command("init", "write a target folder that runs: interface, properties, golden mission, "
                "suts.toml and a standard-library adapter", "harness.campaign.from_bag:init_main")
    c.add_argument("dir", help="the folder to write (created; existing files are never overwritten)")
    c.add_argument("--from-genom", metavar="FILE.gen", help="derive the interface and properties from a "
                   "GenoM3 component description")
    c.add_argument("--include", "-I", action="append", default=[], metavar="DIR",
                   help="with --from-genom: a folder #include searches, after the .gen file's own (repeatable)")
    c.add_argument("--from-ros2", metavar="COMMAND", help="derive the whole target (interface, ROS 2 mapping, SUTs "
                   "per installed distro, golden mission, properties) from the ROS 2 graph COMMAND brings up")
    c.add_argument("--from-bag", metavar="BAG", help="with --from-ros2: the golden mission is the session recorded in "
                   "this rosbag2 bag (MCAP or SQLite3, with service and action introspection)")

    c = command("shrink", "reduce a bad trace's script to the smallest one showing the same bad behaviour",
                "harness.campaign.shrink:main")
    c.add_argument("trace_id", type=int, help="a hung trace, or one with an FN or FP verdict")
    c.add_argument("--property", help="shrink the FN (else FP) on this property id (default: the hang, "
                                      "else the trace's first FN or FP)")
    c.add_argument("--verdict", choices=("FN", "FP"), help="with --property: keep this verdict (default: FN, else FP)")
    c.add_argument("--mission", help="mission folder (default: the trace's campaign's); its suts.toml "
                                     "may define the trace's external SUT")
    c.add_argument("--sut", help="the trace's SUT, named again: an external SUT's command is never "
                                 f"read from the store{EXTERNAL_HELP}")
    c.add_argument("--run-stored-command", action="store_true",
                   help="run the external SUT's command recorded in the store (only for a store you trust)")
    c.add_argument("--out", help="folder of the .mission file (default: shrunk/ beside the store)")
    db(c)

    c = command("analyze", "(re)materialise verdicts from the stored traces and print Tables II-IV",
                "harness.report.junit:analyze")
    c.add_argument("--properties", help="properties file (default: properties.toml of the campaign's mission)")
    c.add_argument("--interface", help="interface description the properties name "
                                       "(default: interface.toml beside the properties file)")
    c.add_argument("--epsilon", type=SECONDS,
                   help=f"seconds within which near events may be reordered (default: the last analysis's, "
                        f"else {DEFAULT_EPSILON_S})")
    c.add_argument("--junit", metavar="FILE", help="also write the verdicts as JUnit XML for a CI server: a test "
                   "case per variant and property, failures for FN, FP, hung and crashed traces")
    c.add_argument("--fail-on", metavar="KINDS", default="", help="comma-separated among fn, fp, hung, crashed: "
                   "exit with status 1 when any judged trace shows one (a CI gate; default: never)")
    db(c)

    c = command("diff", "what the last analysis changed: verdict transitions, Tables II-IV", "harness.analysis.diff:main")
    db(c)

    c = command("explain", "the events that decided a verdict, its margin and what would flip it",
                "harness.analysis.explain:main")
    c.add_argument("trace_id", type=int, help="a trace id")
    c.add_argument("property", help="a property id, as the properties file spells it")
    c.add_argument("rqst_id", type=int, nargs="?", help="a request id (default: every request judged)")
    db(c)

    c = command("report", "write the HTML report and CSV tables from the store alone", "harness.report.build:main")
    c.add_argument("--out", help="output folder (default: the folder of the --db store)")
    c.add_argument("--trace", type=int, action="append", default=[],
                   help="write only the page of this trace id into the report, on demand (repeatable)")
    db(c)

    c = command("import", "load foreign traces (CSV, JSON lines, Parquet, ROS bags) into the store",
                "harness.campaign.importing:main")
    c.add_argument("file", help="a .csv, .jsonl or .parquet file with the events columns, or a ROS 1 .bag, a "
                                "rosbag2 folder (or its .mcap/.db3), or a folder of bags (docs/ros.md)")
    c.add_argument("--interface", required=True, help="interface description giving the reply classes")
    c.add_argument("--ros", help="a bag's mapping file (default: ros.toml beside the interface)")
    db(c)

    c = command("export", "write every table and view of the store as Parquet or CSV files, with a manifest",
                "harness.store.export:main")
    c.add_argument("dir", help="output folder, created if missing")
    c.add_argument("--format", choices=("parquet", "csv"), default="parquet", help="file format (default: %(default)s)")
    db(c)

    c = command("sql", "run ad-hoc SQL against the store and print an aligned table", "harness.store.sqlshell:main")
    c.add_argument("query", help="a SQL query, e.g. \"select * from trace_robustness\"")
    db(c)
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
    module, function = args.target.split(":")
    if getattr(args, "rosbag", None):  # the ROS launcher reads it from the environment it inherits
        Path(args.rosbag).mkdir(parents=True, exist_ok=True)
        os.environ[ROSBAG_ENV] = str(Path(args.rosbag).resolve())
    try:
        return getattr(importlib.import_module(module), function)(args) or 0
    except UntimelyError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as e:
        return _stopped(e.args[0], e.signum) if isinstance(e, processes.Stopped) else _stopped()
    except RuntimeError as e:
        return _stopped() if str(e).startswith(DUCKDB_INTERRUPTED) else _crashed(args.command)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except Exception:
        return _crashed(args.command)
    finally:
        os.environ.pop(ROSBAG_ENV, None)
