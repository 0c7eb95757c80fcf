"""What several commands share: the argparse types that check a flag's value (each check lives
here once; the layers below trust a typed request), the options that several commands take, and
the conversion of parsed flags into a command's typed request."""
from __future__ import annotations

import argparse
import dataclasses
import os
import re
from functools import cache

from harness import DEFAULT_DB, DEFAULT_MISSION_DIR
from harness.errors import UntimelyError

DEFAULT_DB_TEXT = str(DEFAULT_DB)
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


@cache
def variants_help() -> str:
    """The default mission's variants, read from its layer description."""
    try:
        from harness.target.mission import load_layer
        layer = load_layer(DEFAULT_MISSION_DIR)
    except UntimelyError:
        return "those of the mission folder's layer.toml"
    return f"{', '.join(layer.variants)} (for {DEFAULT_MISSION_DIR.name}; others: the mission folder's layer.toml)"


def time_scale(c: argparse.ArgumentParser) -> None:
    c.add_argument("--time-scale", type=SCALE, help="external SUTs: mission seconds per wall second "
                   "(1 = real time; default: the SUT's own, else 1)")


def rosbag(c: argparse.ArgumentParser) -> None:
    """--rosbag is the process's business (cli.py hands it to the ROS launcher through the
    environment), so it stays out of the typed requests."""
    c.add_argument("--rosbag", metavar="DIR", help="ROS SUTs: record each run's bag as DIR/trace-ID.bag "
                   "with Debian's rosbag (docs/ros.md)")


def db(c: argparse.ArgumentParser, help: str = "the DuckDB store") -> None:
    c.add_argument("--db", default=DEFAULT_DB_TEXT, help=f"{help} (default: %(default)s)")


def typed(request: type, namespace: argparse.Namespace):
    """The command's typed request, made of the parsed flags its dataclass names."""
    return request(**{f.name: getattr(namespace, f.name) for f in dataclasses.fields(request)})
