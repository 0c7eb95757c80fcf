"""`python -m harness COMMAND`: the bench's command line (DESIGN §7)."""
from __future__ import annotations

import argparse
import gc
import importlib
import os
import sys
from pathlib import Path

from harness import DEFAULT_DB, DEFAULT_EPSILON_S, DEFAULT_MISSION_DIR
from harness.errors import UntimelyError
from harness.store.database import discard_if_empty

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
        prog="python -m harness",
        description="Untimely: mutate a mission script, run it against a simulated functional "
                    "layer, store every request and reply in DuckDB, judge traces with SQL oracles.")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name, help, target):
        c = sub.add_parser(name, help=help, description=help)
        c.set_defaults(target=target)
        return c

    def time_scale(c):
        c.add_argument("--time-scale", type=float, help="external SUTs: mission seconds per wall second "
                       "(1 = real time; default: the SUT's own, else 1)")

    def db(c, help="the DuckDB store"):
        c.add_argument("--db", default=str(DEFAULT_DB), help=f"{help} (default: %(default)s)")

    c = command("run", "run one script on one variant, store and summarise its trace", "harness.campaign.adhoc:main")
    c.add_argument("mission", help="a mission script, e.g. missions/dala/golden.mission")
    c.add_argument("--sut", required=True, help=f"implementation variant: {variants_help}{EXTERNAL_HELP}")
    c.add_argument("--seed", type=int, default=0, help="seed of the observation delays (default: 0)")
    c.add_argument("--interface", help="interface description (default: interface.toml beside the script)")
    c.add_argument("--world", help="world description (default: world.toml beside the script)")
    c.add_argument("--max-delay", type=float, default=0.003,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    time_scale(c)
    db(c)

    c = command("campaign", "run golden + seeded mutants on each variant; resumable", "harness.campaign.campaign:main")
    c.add_argument("--mission", default=str(DEFAULT_MISSION_DIR), help="mission folder (default: %(default)s)")
    c.add_argument("--mutants", type=int, default=300, help="number of mutants (default: %(default)s)")
    c.add_argument("--sut", help="comma-separated SUTs (default: the layer.toml's default_suts): "
                   f"variants {variants_help}{EXTERNAL_HELP}")
    c.add_argument("--seed", type=int, default=2012, help="campaign seed (default: %(default)s)")
    c.add_argument("--jobs", type=int, default=0, help="worker processes, 0 = all cores (default: %(default)s)")
    c.add_argument("--strategy", choices=("random", "targeted", "focused"), default="random",
                   help="random: the paper's operators; targeted: mutants aimed at falsifying the "
                        "least-covered properties' conditions; focused: short tests, one per way to "
                        "falsify a condition, until the campaign decides it is done (default: %(default)s)")
    c.add_argument("--budget", metavar="DURATION",
                   help="focused only: the mission time all runs may take, shrink runs included "
                        "(4000s, 40m, 1h; default: none, the stopping rule ends the campaign)")
    c.add_argument("--ops-per-mutant", type=int, default=None,
                   help="mutation operations per mutant (default: 1 random, 3 targeted)")
    c.add_argument("--shrink", action="store_true",
                   help="then shrink one representative trace of each distinct bad behaviour "
                        "(focused: each new finding as it shows, within the budget)")
    c.add_argument("--time-mutations", action="store_true", help="also drop waits and change sleeps")
    c.add_argument("--cluster", metavar="ADDRESS", help="run on a Dask cluster: a scheduler address "
                   "(tcp://HOST:8786) or local:N for N local workers; needs the cluster extra (docs/cluster.md)")
    c.add_argument("--max-delay", type=float, default=0.003,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    time_scale(c)
    db(c)

    c = command("shrink", "reduce a bad trace's script to the smallest one showing the same bad behaviour",
                "harness.campaign.shrink:main")
    c.add_argument("trace_id", type=int, help="a hung trace, or one with an FN or FP verdict")
    c.add_argument("--property", help="shrink the FN (else FP) on this property id (default: the hang, "
                                      "else the trace's first FN or FP)")
    c.add_argument("--verdict", choices=("FN", "FP"), help="with --property: keep this verdict (default: FN, else FP)")
    c.add_argument("--mission", help="mission folder (default: the trace's campaign's)")
    c.add_argument("--out", help="folder of the .mission file (default: shrunk/ beside the store)")
    db(c)

    c = command("analyze", "(re)materialise verdicts from the stored traces and print Tables II-IV",
                "harness.analysis.analyzer:main")
    c.add_argument("--properties", help="properties file (default: properties.toml of the campaign's mission)")
    c.add_argument("--interface", help="interface description the properties name "
                                       "(default: interface.toml beside the properties file)")
    c.add_argument("--epsilon", type=float,
                   help=f"seconds within which near events may be reordered (default: the last analysis's, "
                        f"else {DEFAULT_EPSILON_S})")
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

    c = command("import", "load foreign traces (CSV, JSON lines, Parquet) into the store",
                "harness.store.importer:main")
    c.add_argument("file", help="a .csv, .jsonl or .parquet file with the events columns")
    c.add_argument("--interface", required=True, help="interface description giving the reply classes")
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
    args = _parser().parse_args(argv)
    new_store = None if getattr(args, "db", None) in (None, ":memory:") or Path(args.db).exists() else args.db
    status = _run(args)
    if status and new_store:  # e.g. --sut nonexistent: leave no empty store behind
        gc.collect()  # the failed command's connection, held by its traceback until now
        discard_if_empty(new_store)
    return status


def _run(args) -> int:
    module, function = args.target.split(":")
    try:
        return getattr(importlib.import_module(module), function)(args) or 0
    except UntimelyError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("stopped (Ctrl-C); the store keeps every finished transaction", file=sys.stderr)
        return 130
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
