"""Values as text: aligned plain-text tables for the terminal (numbers right-aligned, text
left-aligned), and the one way a rate is shown, in the terminal and in the report alike."""
from __future__ import annotations

from numbers import Number


def percent(rate: float | None) -> str:
    """A rate in [0, 1] as a percentage with one decimal, "-" for NULL (no case to count)."""
    return "-" if rate is None else f"{100 * rate:.1f}"


def counted(n: int, noun: str) -> str:
    """`n` and the noun, plural unless n is 1: "1 verdict", "3 verdicts"."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def rate_interval(rate: float | None, low: float | None, high: float | None, n: int | None) -> str:
    """A rate with its 95% interval and count, e.g. "87.5 [61.7, 96.5] n=16"; "- n=0" without cases."""
    if not n:
        return "- n=0"
    return f"{percent(rate)} [{percent(low)}, {percent(high)}] n={n}"


def with_orders(text: str, lowest: float | None, highest: float | None) -> str:
    """A rate's text and, after it, the interval in which the rate lies whatever the order of the events
    closer than epsilon was ("o" for order): the lowest and highest rate its verdicts' alternatives allow."""
    return f"{text} o=[{percent(lowest)}, {percent(highest)}]"


def cell(value, null: str = "NULL") -> str:
    if value is None:
        return null
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def format_table(columns: list[str], rows: list[tuple], null: str = "NULL") -> str:
    """One header line, a rule, one line per row; trailing blanks stripped."""
    texts = [[cell(v, null) for v in row] for row in rows]
    widths = [max([len(c)] + [len(r[i]) for r in texts]) for i, c in enumerate(columns)]
    values = [[r[i] for r in rows if r[i] is not None] for i in range(len(columns))]
    numeric = [bool(v) and all(isinstance(x, Number) and not isinstance(x, bool) for x in v) for v in values]

    def line(values):
        return "  ".join(v.rjust(w) if num else v.ljust(w)
                         for v, w, num in zip(values, widths, numeric)).rstrip()
    return "\n".join([line(columns), "  ".join("-" * w for w in widths)] + [line(r) for r in texts])


def real_time_factor(sim_s: float, wall_s: float) -> str:
    """Mission seconds per wall second, e.g. "1,234x", "0.87x" (a real-time run: its own factor,
    never rounded to 0x), "-" without wall time."""
    if not wall_s:
        return "-"
    speed = sim_s / wall_s
    return f"{speed:,.0f}x" if speed >= 10 else f"{speed:.2g}x"
