"""`make paper`: the paper's Tables II-IV beside ours, written to docs/paper.md.

The paper's figures are transcribed in paper.toml beside this file, with the reason for each cell
of ours that differs. Ours come from a store of the default campaign (Tables II-IV as the views
compute them): each figure as observed, and the interval in which it lies whatever the order of the
events closer than epsilon was (each uncertain verdict taking itself or one of its alternatives).

    python -m harness.report.paper --db reports/paper.duckdb --out docs/paper.md
"""
from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

from harness.errors import StoreError, UntimelyError
from harness.store.analysis_reads import analysis_epsilon
from harness.store.database import connect
from harness.store.report_reads import mutant_counts, whole
from harness.textable import percent

PAPER = Path(__file__).with_name("paper.toml")
# A rate of ours differs from the paper's when they are at least this far apart: the paper gives
# one decimal of a percentage.
SAME = 0.0005


def _ours(con) -> dict:
    def by(view, key):
        return {key(r): r for r in whole(con, view)}
    return {"II": by("trace_robustness", lambda r: r["sut"]),
            "III": by("tp_rates", lambda r: (r["sut"], r["family"])),
            "IV": by("fp_rates", lambda r: (r["sut"], r["family"]))}


def _pct(rate) -> str:
    return "-" if rate is None else f"{percent(rate)}%"


def _between(o: dict, column: str, rate: bool = True) -> str:
    """A figure's interval over the orders of events: "[lowest, highest]"."""
    show = _pct if rate else str
    return f"[{show(o.get(f'{column}_min'))}, {show(o.get(f'{column}_max'))}]"


def _table_ii(paper: dict, ours: dict) -> list[str]:
    lines = ["| variant | | traces | hung | with FN | with FP | bad | T_ROB |", "|---|---|---|---|---|---|---|---|"]
    for v in paper["variants"]:
        p, o = paper["table_ii"][v], ours["II"][v]
        name = paper["names"][v]
        lines.append(f"| {name} | paper | {p['total']} | {p['hung']} | {p['with_fn']} | {p['with_fp']} | "
                     f"{p['bad']} | {_pct(p['t_rob'])} |")
        lines.append(f"| | ours, all | {o['total']} | {o['hung']} | {o['with_fn']} | {o['with_fp']} | "
                     f"{o['bad']} | {_pct(o['t_rob'])} |")
        lines.append(f"| | ours, any order | {o['total']} | {o['hung']} | {_between(o, 'with_fn', False)} | "
                     f"{_between(o, 'with_fp', False)} | {_between(o, 'bad', False)} | {_between(o, 't_rob')} |")
    return lines


def _rates(paper: dict, ours: dict, table: str, rate: str) -> list[str]:
    variants = paper["variants"]
    lines = ["| family | " + " | ".join(f"{paper['names'][v]} paper | ours | ours, any order" for v in variants) + " |",
             "|---|" + "---|" * 3 * len(variants)]
    for f in paper["families"]:
        cells = []
        for v in variants:
            o = ours[table].get((v, f), {})
            cells += [_pct(paper[f"table_{table.lower()}"][v][f]), _pct(o.get(rate)), _between(o, rate)]
        lines.append(f"| {f} | " + " | ".join(cells) + " |")
    return lines


def differences(paper: dict, ours: dict) -> list[tuple[str, str]]:
    """(cell, what differs) for every cell of ours that differs from the paper's: Table II per variant
    (the number of runs always differs), Tables III and IV per family and variant."""
    found = []
    for v in paper["variants"]:
        p, o = paper["table_ii"][v], ours["II"][v]
        found.append((f"II.{v}", f"Table II, {paper['names'][v]}: paper {p['hung']} hung, {p['with_fn']} with FN, "
                      f"{p['with_fp']} with FP of {p['total']} (T_ROB {_pct(p['t_rob'])}); ours {o['hung']} hung, "
                      f"{o['with_fn']} with FN ({_between(o, 'with_fn', False)} in any order), {o['with_fp']} "
                      f"with FP ({_between(o, 'with_fp', False)}) of {o['total']} (T_ROB {_pct(o['t_rob'])}, "
                      f"{_between(o, 't_rob')} in any order of the events closer than epsilon)."))
    for table, rate, title in (("III", "tp_rate", "true positive rate"), ("IV", "fp_rate", "false positive rate")):
        for f in paper["families"]:
            for v in paper["variants"]:
                theirs, o = paper[f"table_{table.lower()}"][v][f], ours[table].get((v, f), {})
                if o.get(rate) is None or abs(o[rate] - theirs) >= SAME:
                    found.append((f"{table}.{f}.{v}",
                                  f"Table {table}, {f} on {paper['names'][v]}: {title} {_pct(theirs)} in the paper, "
                                  f"{_pct(o.get(rate))} here ({_between(o, rate)} in any order of the events closer "
                                  f"than epsilon; n = {o.get('n', 0)})."))
    return found


def write(db: str, out: Path) -> list[str]:
    """Write the comparison; returns the cells that differ without a reason in paper.toml."""
    paper = tomllib.loads(PAPER.read_text(encoding="utf-8"))
    con = connect(db, read_only=True)
    try:
        ours = _ours(con)
        runs = mutant_counts(con)
        epsilon = analysis_epsilon(con)
    except Exception as e:  # noqa: BLE001 - a store without a judged default campaign
        raise StoreError(f"{db!r} holds no judged campaign ({e}); make paper runs one") from None
    finally:
        con.close()
    missing = [v for v in paper["variants"] if v not in ours["II"]]
    if missing:
        raise UntimelyError(f"{db!r} has no traces of {', '.join(missing)}; the paper's tables need "
                            f"{', '.join(paper['variants'])} (the default campaign)")
    why = paper.get("why", {})
    found = differences(paper, ours)
    text = ["# The paper's Tables II-IV beside ours", "",
            "Generated by `make paper` (harness/report/paper.py) from a fresh default campaign: "
            f"{runs[0]} mutants of the golden Dala mission, {runs[1]} valid, run with the golden script on "
            f"the simulated GenoM, BIP-A and BIP-B layers and judged with epsilon {epsilon:g} s. The paper "
            f"ran {paper['valid_mutants']} valid mutants of {paper['mutants']} on the real layers. Each of our "
            "figures is given as observed (counting every FN and FP, as the paper did) and as the interval in "
            "which it lies whatever the order of the events closer than epsilon was, each uncertain verdict "
            "taking itself or one of its alternatives (docs/analyzer.md): the true figure lies in it. The paper "
            "corrected its BIP-B column by hand for false observations; the intervals say how far such a "
            "correction can go in every column.", "",
            "## Table II: per-trace results", "", *_table_ii(paper, ours), "",
            "## Table III: true positive rates", "", *_rates(paper, ours, "III", "tp_rate"), "",
            "## Table IV: false positive rates", "", *_rates(paper, ours, "IV", "fp_rate"), "",
            "## Why they differ", ""]
    for cell, what in found:
        text += [f"**{what}** {why.get(cell, 'No reason recorded yet: add one to harness/report/paper.toml.')}", ""]
    out.write_text("\n".join(text), encoding="utf-8")
    return [cell for cell, _ in found if cell not in why]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", default="reports/paper.duckdb")
    parser.add_argument("--out", type=Path, default=Path("docs/paper.md"))
    args = parser.parse_args(argv)
    try:
        unexplained = write(args.db, args.out)
    except UntimelyError as e:
        print(f"error: {e}")
        return 2
    print(f"wrote {args.out}" + (f"; no reason recorded for {', '.join(unexplained)}" if unexplained else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
