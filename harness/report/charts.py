"""Inline SVG charts of the index page: grouped rate bars and a stacked verdict mix."""
from __future__ import annotations

from markupsafe import Markup

from harness.report.svg import add, markup, nice_step, svg

PLOT_H, LEFT, BOTTOM, TOP = 160, 46, 56, 24
BAR_W, GAP = 16, 14
CHAR_W = 7  # an upper bound of the width of one character of the 11 px labels
LEGEND_GAP = 32  # from the bottom of the plot to the legend's baseline, below the tick labels
MIN_PART_W = 4  # a verdict kind with a single case stays visible in the verdict mix


def grouped_bars(title: str, categories: list[str], series: list[str],
                 values: dict[tuple[str, str], float | None], full_scale: bool = True,
                 intervals: dict[tuple[str, str], tuple[float, float]] | None = None) -> Markup:
    """Rates in [0, 1]: one group of bars per category, one bar per series, each with a whisker
    over its confidence interval when `intervals` gives one.

    full_scale draws 0-100 %; otherwise the axis stops just above the largest rate (or interval),
    so that rare events (false positives) stay visible.
    """
    intervals = intervals or {}
    top = max([v for v in values.values() if v is not None] + [hi for _, hi in intervals.values()] + [0.0])
    y_max = 1.0 if full_scale or top == 0 else min(1.0, nice_step(top, 4) * 4)
    group_w = max(len(series) * BAR_W, max(CHAR_W * len(c) for c in categories)) + GAP
    width = LEFT + len(categories) * group_w + 20
    legend_w = sum(12 + CHAR_W * len(s) + 14 for s in series)
    root = svg(max(width, LEFT + legend_w), TOP + PLOT_H + BOTTOM, "chart", title)
    y = lambda v: TOP + PLOT_H * (1 - v / y_max)  # noqa: E731
    step = nice_step(y_max, 4)
    for i in range(int(round(y_max / step)) + 1):
        add(root, "line", css_class="grid", x1=LEFT, x2=width - 10, y1=y(i * step), y2=y(i * step))
        add(root, "text", f"{100 * i * step:g}%", css_class="tick", x=LEFT - 4, y=y(i * step) + 4,
            text_anchor="end")
    for c, category in enumerate(categories):
        center = LEFT + GAP / 2 + c * group_w + (group_w - GAP) / 2
        x0 = center - len(series) * BAR_W / 2
        add(root, "text", category, css_class="tick", x=center, y=TOP + PLOT_H + 14, text_anchor="middle")
        for s, name in enumerate(series):
            v = values.get((category, name))
            tip = f"{name}, {category}: " + ("no case" if v is None else f"{100 * v:.1f}%")
            if v is None:
                add(root, "text", "-", css_class="tick", x=x0 + (s + 0.5) * BAR_W, y=y(0) - 2,
                    text_anchor="middle", title=tip)
                continue
            interval = intervals.get((category, name))
            if interval:
                tip += f" [{100 * interval[0]:.1f}, {100 * interval[1]:.1f}]"
            add(root, "rect", css_class=f"series-{s}", x=x0 + s * BAR_W, y=y(v), width=BAR_W - 2,
                height=max(y(0) - y(v), 0.5), title=tip)
            if interval:
                mid = x0 + s * BAR_W + (BAR_W - 2) / 2
                add(root, "line", css_class="whisker", x1=mid, x2=mid, y1=y(interval[0]), y2=y(interval[1]),
                    title=tip)
    _legend(root, series, [f"series-{s}" for s in range(len(series))], TOP + PLOT_H + LEGEND_GAP)
    return markup(root)


def stacked_bars(title: str, rows: list[str], parts: list[str],
                 counts: dict[tuple[str, str], int]) -> Markup:
    """One horizontal 100 % bar per row, split by part (e.g. verdict kind), on a 0-100 % scale,
    with counts on hover; a part with few cases is drawn at least MIN_PART_W wide."""
    label_w, plot_w, row_h = 80, 560, 22
    plot_h = len(rows) * row_h
    root = svg(label_w + plot_w + 20, TOP + plot_h + BOTTOM, "chart", title)
    for i in range(5):
        x = label_w + plot_w * i / 4
        add(root, "line", css_class="grid", x1=x, x2=x, y1=TOP, y2=TOP + plot_h + 2)
        add(root, "text", f"{25 * i}%", css_class="tick", x=x, y=TOP + plot_h + 14, text_anchor="middle")
    for r, row in enumerate(rows):
        total = sum(counts.get((row, p), 0) for p in parts)
        y0 = TOP + r * row_h
        add(root, "text", row, css_class="tick", x=label_w - 6, y=y0 + 14, text_anchor="end")
        shown = [(p, counts.get((row, p), 0)) for p in parts if counts.get((row, p), 0)]
        x = float(label_w)
        for (part, n), w in zip(shown, _widths([n for _, n in shown], plot_w)):
            add(root, "rect", css_class=f"v-{part}", x=x, y=y0 + 2, width=w, height=row_h - 6,
                title=f"{row}: {n} {part} ({100 * n / total:.1f}% of {total})")
            x += w
    _legend(root, parts, [f"v-{p}" for p in parts], TOP + plot_h + LEGEND_GAP)
    return markup(root)


def _widths(counts: list[int], total_w: float) -> list[float]:
    """Widths proportional to counts, each at least MIN_PART_W, summing to total_w (the wide
    parts give up what the narrow ones gain)."""
    total = sum(counts)
    narrow = [n * total_w / total < MIN_PART_W for n in counts]
    room = total_w - MIN_PART_W * sum(narrow)
    wide_total = sum(n for n, is_narrow in zip(counts, narrow) if not is_narrow)
    return [MIN_PART_W if is_narrow else room * n / wide_total for n, is_narrow in zip(counts, narrow)]


def _legend(root, names: list[str], classes: list[str], y: float) -> None:
    x = float(LEFT)
    for name, css in zip(names, classes):
        add(root, "rect", css_class=css, x=x, y=y - 9, width=10, height=10)
        add(root, "text", name, css_class="tick", x=x + 13, y=y)
        x += 12 + CHAR_W * len(name) + 14
