"""Hostile inputs over every entry point a user reaches (issue 19): mission scripts, target files,
import files, flags and stores. Each case builds its files in a fresh folder and gives the command
line; it expects either a refusal (exit 2, a message quoting the file or flag and the bad value) or
the right outcome (a `check` on what the command made). test_corpus.py runs them."""
from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path
from typing import Callable

import duckdb
import pyarrow as pa
import pyarrow.parquet as pq

from harness import DEFAULT_MISSION_DIR

GOLDEN = (DEFAULT_MISSION_DIR / "golden.mission").read_text()
EVENT = {"trace_id": "a", "seq": 1, "t": 0.0, "kind": "request", "rqst_id": 1, "module": "rflex", "service": "Init"}


class Place:
    """A test's folder: a copy of the Dala target in `target`, stores made on demand."""

    def __init__(self, root: Path, cli):
        self.root, self.cli = root, cli
        self.target = root / "dala"
        shutil.copytree(DEFAULT_MISSION_DIR, self.target)
        self.db = root / "store.duckdb"

    def file(self, name: str, content: str | bytes) -> Path:
        path = self.root / name
        path.write_bytes(content.encode() if isinstance(content, str) else content)
        return path

    def edit(self, name: str, old: str, new: str) -> Path:
        path = self.target / name
        text = path.read_text()
        assert old in text, (name, old)
        path.write_text(text.replace(old, new, 1))
        return path

    def run_store(self, analysed: bool = False) -> Path:
        """A store holding one run of the golden script on genom; analysed if asked."""
        assert self.cli(["run", str(self.target / "golden.mission"), "--sut", "genom", "--db", str(self.db)]) == 0
        if analysed:
            assert self.cli(["analyze", "--db", str(self.db)]) == 0
        return self.db


@dataclass(frozen=True)
class Case:
    name: str
    argv: Callable[[Place], list[str]]
    expect: str  # in the message (a refusal) or in the output (an outcome)
    code: int = 2
    prepare: Callable[[Place], object] | None = None  # what to break before the command
    check: Callable[[Place], None] | None = None  # the outcome the command must leave behind


def run(p: Place, script: str = "golden.mission") -> list[str]:
    return ["run", str(p.target / script), "--sut", "genom", "--db", str(p.db)]


def campaign(p: Place, *more: str) -> list[str]:
    return ["campaign", "--mission", str(p.target), "--mutants", "1", "--jobs", "1", *more, "--db", str(p.db)]


def analyze(p: Place) -> list[str]:
    return ["analyze", "--db", str(p.db)]


def script(text: str | bytes) -> Callable[[Place], object]:
    return lambda p: (p.target / "hostile.mission").write_bytes(text.encode() if isinstance(text, str) else text)


def run_hostile(p: Place) -> list[str]:
    return run(p, "hostile.mission")


def _loop_for(name: str) -> Callable[[Place], None]:
    def replace(p: Place) -> None:
        (p.target / name).unlink(missing_ok=True)
        (p.target / name).symlink_to(p.target / name)
    return replace


def _folder_for(name: str) -> Callable[[Place], None]:
    def replace(p: Place) -> None:
        (p.target / name).unlink()
        (p.target / name).mkdir()
    return replace


def _with_bom(name: str) -> Callable[[Place], object]:
    return lambda p: (p.target / name).write_bytes(b"\xef\xbb\xbf" + (p.target / name).read_bytes())


def _edit(name: str, old: str, new: str, stored: bool = False) -> Callable[[Place], None]:
    def edit(p: Place) -> None:
        if stored:
            p.run_store()
        p.edit(name, old, new)
    return edit


def _requests(p: Place) -> int:
    con = duckdb.connect(str(p.db), read_only=True)
    try:
        return con.execute("select count(*) from events where kind = 'request'").fetchone()[0]
    finally:
        con.close()


def _one_request(p: Place) -> None:
    assert _requests(p) == 1


SCRIPTS = [
    Case("script: a folder", lambda p: run(p, "."), "dala: is a folder, not a file; pass the file itself"),
    Case("script: a symlink loop", run_hostile, "hostile.mission: is a symbolic link that loops",
         prepare=_loop_for("hostile.mission")),
    Case("script: not UTF-8", run_hostile, "hostile.mission:2: not UTF-8 (byte 0xe9)",
         prepare=script(b"send rflex.Init\n# caf\xe9\n")),
    Case("script: no step", run_hostile, "hostile.mission:1: the script has no steps", prepare=script("# none\n")),
    Case("script: a 1 MB word", run_hostile, "hostile.mission:1: unknown step 'xxxxxxxx",
         prepare=script("x" * 1_000_000 + "\n")),
    Case("script: an unknown service", run_hostile, "hostile.mission:1: unknown service 'rflex.Fly'; module 'rflex' "
         "offers Init", prepare=script("send rflex.Fly\n")),
    Case("script: an argument given twice", run_hostile, "hostile.mission:1: argument 'x' is given twice",
         prepare=script("send ndd.GotoPosition x=1 x=2 y=1\n")),
    Case("script: U+2028 and a form feed in a comment run nothing", run_hostile, "outcome    completed", code=0,
         prepare=script("send rflex.Init as r  # then\u2028send sick.Init\fsend ndd.Init\nwait r\n"),
         check=_one_request),
    Case("script: a byte-order mark is no text", run_hostile, "outcome    completed", code=0,
         prepare=script("\ufeffsend rflex.Init as r\nwait r\n"), check=_one_request),
]

TARGET = [
    Case("interface: a folder", campaign, "interface.toml: is a folder, not a file",
         prepare=_folder_for("interface.toml")),
    Case("layer: a folder", run, "layer.toml: is a folder, not a file", prepare=_folder_for("layer.toml")),
    *(Case(f"{name}: a folder, in a campaign", campaign, f"{name}: is a folder, not a file", prepare=_folder_for(name))
      for name in ("world.toml", "golden.mission", "layer.toml", "properties.toml")),
    Case("golden.mission: a symlink loop, in a campaign", campaign, "golden.mission: is a symbolic link that loops",
         prepare=_loop_for("golden.mission")),
    Case("interface: a module that is a number", campaign, "interface.toml:23: modules.drone = 5; give a table",
         prepare=_edit("interface.toml", "[modules.rflex]", "[modules]\ndrone = 5\n[modules.rflex]")),
    Case("interface: a byte-order mark", run, "outcome    completed", code=0, prepare=_with_bom("interface.toml")),
    Case("interface: --interface given a mission file", lambda p: run(p) + ["--interface", str(p.target / "golden.mission")],
         "golden.mission: not valid TOML"),
    Case("layer: a negative duration", run, "layer.toml:17: timing.Stop: run_s = -0.05; give a number of seconds >= 0",
         prepare=_edit("layer.toml", "run_s = 0.05", "run_s = -0.05")),
    *(Case(f"layer: behaviour = os, {command.__name__}", command, "layer.toml:7: behaviour = 'os' has no "
           "build(env, world_file) function", prepare=_edit("layer.toml", '"harness.sut.dala.behaviour"', '"os"'))
      for command in (run, campaign)),
    Case("layer: default_suts = []", campaign, "layer.toml:12: layer.default_suts = []; give a non-empty list",
         prepare=_edit("layer.toml", 'default_suts = ["genom", "bip-a", "bip-b"]', "default_suts = []")),
    Case("world: an unknown key", run, "unknown key 'speed'; [rover] takes x, y, heading_deg, radius",
         prepare=_edit("world.toml", "[rover]", "[rover]\nspeed = 3")),
    Case("properties: r_p as a list", analyze, "r_p = ['wait_init']; give the rejection code",
         prepare=_edit("properties.toml", 'r_p = "wait_init"', 'r_p = ["wait_init"]', stored=True)),
    Case("properties: min = nan in the interface", run, "min = nan; give a finite number",
         prepare=_edit("interface.toml", "min = 30.0", "min = nan")),
    Case("suts.toml: env as a list", lambda p: campaign(p, "--sut", "mine"),
         "suts.toml:3: mine.env = ['A=1']; give a table of NAME = \"text\"",
         prepare=lambda p: (p.target / "suts.toml").write_text('[mine]\ncommand = "x"\nenv = ["A=1"]\n')),
    Case("suts.toml: an unclosed quote", lambda p: campaign(p, "--sut", "mine"),
         "suts.toml:1: mine: command = \"python 'adapter.py\": No closing quotation; close the quote",
         prepare=lambda p: (p.target / "suts.toml").write_text('[mine]\ncommand = "python \'adapter.py"\n')),
]


def _import(make: Callable[[Place], Path]) -> Callable[[Place], list[str]]:
    return lambda p: ["import", str(make(p)), "--interface", str(p.target / "interface.toml"), "--db", str(p.db)]


def _stamped(p: Place) -> Path:
    path = p.root / "stamped.parquet"
    pq.write_table(pa.table({**{k: [v] for k, v in EVENT.items()}, "args": [{"at": datetime(2024, 5, 1)}]}), path)
    return path


IMPORTS = [
    Case("import: 200,000 nested levels", _import(lambda p: p.file(
        "deep.jsonl", json.dumps(EVENT) + "\n" + "[" * 200_000 + "]" * 200_000 + "\n")),
         "deep.jsonl:line 2: JSON nested too deeply"),
    Case("import: Parquet args holding a timestamp", _import(_stamped),
         "stamped.parquet:row 1: args holds {'at': datetime.datetime(2024, 5, 1, 0, 0)}, which is no JSON value"),
    Case("import: a CSV column twice", _import(lambda p: p.file(
        "twice.csv", "trace_id,seq,t,kind,rqst_id,module,service,seq\na,1,0,request,1,rflex,Init,1\n")),
         "twice.csv:1: the header names the column 'seq' twice; keep one"),
    Case("import: a folder", _import(lambda p: p.target), "dala: is a folder that holds no bag"),
    Case("import: a CSV with a byte-order mark, as a spreadsheet saves it", _import(lambda p: p.file(
        "bom.csv", "\ufefftrace_id,seq,t,kind,rqst_id,module,service,reply\na,1,0,request,1,rflex,Init,\n"
                   "a,2,0.5,final,1,rflex,Init,ok\n")), "Imported 1 trace (2 events) from", code=0),
    Case("import: JSON lines with a byte-order mark", _import(lambda p: p.file(
        "bom.jsonl", "\ufeff" + json.dumps(EVENT) + "\n")), "Imported 1 trace (1 event) from", code=0),
]


def _flag(*argv: str) -> Callable[[Place], list[str]]:
    return lambda p: [*argv, "--db", str(p.db)]


FLAGS = [
    Case("--seed 10^23", lambda p: run(p) + ["--seed", str(10**23)], "argument --seed: '100000000000000000000000': "
         "give a whole number from -2^63 to 2^63 - 1"),
    *(Case(f"--time-scale {v}", lambda p, v=v: run(p) + ["--time-scale", v], f"argument --time-scale: '{v}': give a "
           "finite factor > 0") for v in ("0", "nan", "inf")),
    *(Case(f"--cluster {v}", lambda p, v=v: campaign(p, "--cluster", v), f"argument --cluster: '{v}': give "
           "tcp://HOST:PORT") for v in ("garbage", "local:0", "local:-1")),
    *(Case(f"--jobs {v}", lambda p, v=v: campaign(p, "--jobs", v), f"argument --jobs: '{v}': give a number of worker "
           "processes from 1 to") for v in ("-1", "10000")),
    Case("--epsilon nan", lambda p: analyze(p) + ["--epsilon", "nan"], "argument --epsilon: 'nan': give a number of "
         "seconds >= 0"),
    Case("--max-delay -1", lambda p: run(p) + ["--max-delay", "-1"], "argument --max-delay: '-1': give a number"),
    Case("--db not UTF-8", lambda p: ["sql", "select 1", "--db", str(p.root).encode().decode() + "/\udcff.duckdb"],
         "/\\udcff.duckdb': not UTF-8 (the store and its files keep UTF-8 names)"),
    Case("--mutants -1", lambda p: campaign(p, "--mutants", "-1"), "--mutants -1: give a number of mutants from 0"),
]


def _unchanged_store(p: Place) -> None:
    assert p.db.read_bytes() == p.kept, "the store changed"
    assert sorted(x.name for x in p.root.iterdir()) == ["dala", "store.duckdb"]


def _keep(p: Place, analysed: bool = True) -> None:
    p.run_store(analysed)
    p.kept = p.db.read_bytes()


STORES = [
    Case("sql: copy to the store itself", lambda p: ["sql", f"copy events to '{p.db}'", "--db", str(p.db)],
         "the sql command is read-only: it writes nothing", prepare=_keep, check=_unchanged_store),
    Case("sql: attach", lambda p: ["sql", f"attach '{p.root / 'other.duckdb'}' as o", "--db", str(p.db)],
         "the sql command is read-only: it writes nothing", prepare=_keep, check=_unchanged_store),
    Case("diff: a never analysed store", _flag("diff"), "has no analysis to compare; run python -m harness analyze",
         prepare=lambda p: _keep(p, analysed=False), check=_unchanged_store),
    Case("explain: a never analysed store", _flag("explain", "1", "PEX(rflex)"), "has no verdicts to explain; run "
         "python -m harness analyze", prepare=lambda p: _keep(p, analysed=False), check=_unchanged_store),
    Case("export: to a file", lambda p: ["export", str(p.target / "golden.mission"), "--db", str(p.db)],
         "golden.mission': it is a file; give a folder", prepare=_keep),
    Case("export: a folder holding other files", lambda p: ["export", str(p.target), "--db", str(p.db)],
         "dala': it holds 'golden.mission', which no earlier export wrote", prepare=_keep),
    Case("export: an unwritable place", lambda p: ["export", "/proc/untimely-export", "--db", str(p.db)],
         "cannot create the folder '/proc/untimely-export' for the export", prepare=_keep, check=_unchanged_store),
    Case("shrink: --out an unwritable place", lambda p: ["shrink", "1", "--out", "/proc/untimely", "--db", str(p.db)],
         "cannot create the folder '/proc/untimely' for the shrunk scripts", prepare=_keep, check=_unchanged_store),
    Case("a store that is a folder", lambda p: ["analyze", "--db", str(p.target)], "cannot open the store"),
    Case("a store that is no DuckDB file", lambda p: ["sql", "select 1", "--db", str(p.target / "golden.mission")],
         "is not a valid DuckDB database file"),
    Case("a missing store", _flag("report"), "no store at"),
]

CASES = SCRIPTS + TARGET + IMPORTS + FLAGS + STORES
