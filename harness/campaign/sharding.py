"""`campaign --shard I/N` and `untimely merge OUT STORE...`: a campaign split over any batch engine.

Every shard generates the same scripts (they are a function of the campaign's arguments) and
stores them all, but runs only its part of the runs: those whose trace id t has
(t - 1) mod N = I - 1. Trace ids and seeds do not depend on who runs what, so the N stores
hold disjoint traces of one campaign; `merge` copies them into a new store, which it then
judges as the last analysis of the shards did. The merged store holds what the unsharded
campaign stores (tests/campaign/test_sharding.py compares their fingerprints).

`merge` refuses, with a message, stores of different campaigns (other arguments or mission
files), the same part twice, a missing part, a part missing some of its traces (naming them), and an
OUT that exists. A shard written before a table existed is read as holding none of its rows.
"""
from __future__ import annotations

import re
from pathlib import Path

from harness.analysis import analyzer
from harness.analysis.summary import analysis_summary
from harness.analysis.explain import judged_files
from harness.analysis.provenance import last_epsilon
from harness.errors import StoreError, UntimelyError
from harness.store import campaign_reads
from harness.store import merge as store_merge
from harness.store.database import connect
from harness.store.record import CampaignRecord, ShrinkRecord, record_of, records
from harness.target.interface import load_interface, load_properties

SHARD = re.compile(r"\s*(\d+)\s*/\s*(\d+)\s*")
# What may differ between the shards of one campaign: the part, the worker count, where the
# mission folder was on each machine (its files' hashes must agree).
LOCAL = ("shard", "jobs", "mission")


def parse(option: str | None) -> list[int] | None:
    """[I, N] of `--shard I/N`, or None for the whole campaign."""
    if option is None:
        return None
    found = SHARD.fullmatch(option)
    if not found or not 1 <= int(found.group(1)) <= int(found.group(2)):
        raise UntimelyError(f"--shard {option!r}: give I/N with 1 <= I <= N, e.g. --shard 2/4 for the second "
                            "of four parts")
    return [int(found.group(1)), int(found.group(2))]


def trace_id(script_id: int, variant: int, variants: int) -> int:
    """The trace id of script `script_id`'s run on the `variant`-th of `variants` variants: a function
    of the script and the variant alone, whoever runs it."""
    return (script_id - 1) * variants + variant + 1


def owns(shard: list[int] | None, trace_id: int) -> bool:
    """Whether this shard (every one, without a shard) makes the run of `trace_id`."""
    return shard is None or (trace_id - 1) % shard[1] == shard[0] - 1


def part(tasks: list, shard: list[int] | None) -> list:
    """The tasks of this shard (all of them without one)."""
    return [t for t in tasks if owns(shard, t.trace_id)]


def share(runs: int, shard: list[int] | None) -> int:
    """How many of a campaign's `runs` runs (trace ids 1..runs) this shard makes."""
    return runs if shard is None else len(range(shard[0] - 1, runs, shard[1]))


def _campaign(con, path: str) -> tuple[CampaignRecord, int, int]:
    """The shard's campaign record and id, and how many shrinks (campaign --shrink) its store holds beside it."""
    rows = [(i, r) for i, _, r in records(con)]
    sharded = [(i, r) for i, r in rows if isinstance(r, CampaignRecord) and r.shard]
    shrinks = [r for _, r in rows if isinstance(r, ShrinkRecord)]
    if len(sharded) != 1 or len(sharded) + len(shrinks) != len(rows):
        raise StoreError(f"{path} is not the store of one shard of a campaign (campaign --shard I/N, alone in "
                         "its store); merge only the stores the shards wrote")
    (campaign_id, config), = sharded
    return config, campaign_id, len(shrinks)


def _missing(con, path: str, campaign_id: int, config: CampaignRecord) -> None:
    """Refuses a shard that lacks runs of its part (an unfinished or cut-short campaign), naming them."""
    variants = len(config.sut)
    scripts = [s for s, _ in campaign_reads.valid_scripts(con, campaign_id)]
    wanted = [t for t in (trace_id(s, v, variants) for s in scripts for v in range(variants))
              if owns(config.shard, t)]
    stored = campaign_reads.campaign_trace_ids(con, campaign_id)
    missing = sorted(t for t in wanted if t not in stored)
    if missing:
        shown = ", ".join(map(str, missing[:10])) + (f" and {len(missing) - 10} more" if len(missing) > 10 else "")
        index, count = config.shard
        raise StoreError(f"{path} lacks {len(missing)} of the {len(wanted)} traces of shard {index}/{count} "
                         f"(trace ids {shown}): its campaign did not finish; rerun its campaign command, which "
                         "resumes it, then merge")


def check(configs: dict[str, CampaignRecord]) -> None:
    """Refuses stores that are not the N distinct parts of one campaign."""
    (first_path, first), *others = configs.items()
    for path, config in others:
        differing = sorted(k for k in CampaignRecord.model_fields if k not in LOCAL and getattr(config, k) != getattr(first, k))
        if differing:
            raise StoreError(f"{path} holds another campaign than {first_path} (its {', '.join(differing)} "
                             "differ); merge the shards of one campaign only")
    count = first.shard[1]
    parts: dict[int, str] = {}
    for path, config in configs.items():
        index, total = config.shard
        if total != count:
            raise StoreError(f"{path} is shard {index}/{total}, {first_path} a shard of {count}: merge the "
                             "shards of one split")
        if index in parts:
            raise StoreError(f"{path} and {parts[index]} are both shard {index}/{count} (a store given twice?); "
                             "give each part once")
        parts[index] = path
    missing = sorted(set(range(1, count + 1)) - set(parts))
    if missing:
        raise StoreError(f"shard(s) {', '.join(f'{i}/{count}' for i in missing)} missing: merge all {count} "
                         "parts, each store once")


def merge(out: str, stores: list[str], properties: str | None = None) -> int:
    """`merge`: the shards' stores copied into the new store `out` and judged."""
    out = Path(out)
    if out.exists():
        raise UntimelyError(f"{out} exists; merge writes a new store: give another OUT or remove it")
    configs, campaign_ids, shrinks, paths = {}, [], 0, [str(Path(s)) for s in stores]
    if len({Path(p).resolve() for p in paths}) != len(paths):
        raise StoreError(f"a store is given twice in {' '.join(paths)}; give each part once")
    for path in paths:
        con = connect(path, read_only=True)
        try:
            configs[path], campaign_id, shrunk = _campaign(con, path)
            _missing(con, path, campaign_id, configs[path])
            campaign_ids.append(campaign_id)
            shrinks += shrunk
            if path == paths[0]:
                properties_file, interface_file = judged_files(con, properties)
                epsilon = last_epsilon(con)
        finally:
            con.close()
    check(configs)
    if not properties_file.is_file():
        raise UntimelyError(f"{properties_file}: no such file, and the merged store is judged with the shards' "
                            "properties; pass --properties FILE (the target's properties.toml)")
    merged = record_of({k: v for k, v in configs[paths[0]].stored().items() if k != "shard"})
    con = connect(out)
    try:
        store_merge.copy(con, paths, campaign_ids, merged)
        interface = load_interface(interface_file)
        analyzer.materialise(con, load_properties(properties_file, interface), epsilon, interface,
                             properties_file, interface_file)
    except BaseException:
        con.close()
        for leftover in (out, out.with_name(out.name + ".wal")):
            leftover.unlink(missing_ok=True)  # no half-merged store
        raise
    traces = campaign_reads.trace_count(con)
    print(f"merged {len(paths)} shards into {out}: {traces} traces, judged against {properties_file} "
          f"(epsilon {epsilon:g} s)\n")
    if shrinks:
        print(f"left out: the {shrinks} shrinks the shards stored (campaign --shrink), their runs and reproducers; "
              f"to shrink the merged findings: untimely campaign --shrink with the shards' options and --db {out}\n")
    print(analysis_summary(con, epsilon))
    con.close()
    return 0
