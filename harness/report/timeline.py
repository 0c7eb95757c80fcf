"""The SVG timeline of one trace: a lane per module, a bar per request, verdicts and world events."""
from __future__ import annotations

import json
from dataclasses import dataclass

from markupsafe import Markup

from harness.report.svg import add, markup, nice_step, svg
from harness.report.tables import yes_no

LEFT, PLOT_W, RIGHT = 120, 1040, 20
AXIS_H, ROW_H, BAR_H, LANE_PAD = 36, 16, 12, 5
MIN_BAR_W = 3  # a rejection is instantaneous; keep it visible and hoverable
MARKED = ("FN", "FP", "TP")  # the verdicts a tester hunts for; TN, op, na, omega stay in tooltips
MARK_W = 17
LABEL_CHAR_W = 6  # an upper bound of the width of one character of a 9 px bar label


@dataclass
class RequestBar:
    """A request as a bar of a trace page's timeline: from its sending to its final reply."""
    rqst_id: int
    module: str
    service: str
    args: str | None
    start: float
    end: float | None = None  # time of the final reply; None = no final reply in the trace
    reply: str | None = None
    reply_class: str | None = None
    lifecycle: str | None = None  # a managed ROS 2 node's state when the request was sent (view lifecycle_states)
    pending: str | None = None  # its transitions requested before and answered after it

    def label(self) -> str:
        args = json.loads(self.args) if self.args else {}
        words = " ".join(f"{k}={v}" for k, v in args.items()) if isinstance(args, dict) else str(args)
        return f"{self.module}.{self.service} {words}".strip()

    @property
    def state(self) -> str | None:
        """The node's lifecycle state in words: `inactive`, `unconfigured (configure pending)`."""
        if self.lifecycle is None:
            return None
        return f"{self.lifecycle} ({self.pending} pending)" if self.pending else self.lifecycle

    @property
    def shown(self) -> str:
        """The bar's label: the service, and the node's lifecycle state where it has one."""
        return f"{self.service} [{self.lifecycle}{'?' if self.pending else ''}]" if self.lifecycle else self.service


@dataclass
class Bar:
    """Where a request is drawn: its bar, and its verdict marks inside it or, if it is too short, after it."""
    request: RequestBar
    verdicts: list[dict]
    x0: float
    x1: float

    @property
    def marked(self) -> list[dict]:
        return [v for v in self.verdicts if v["verdict"] in MARKED]

    @property
    def marks_x(self) -> float:
        inside = self.x1 - self.x0 >= len(self.marked) * (MARK_W + 1) + 2
        return self.x0 + 1 if inside else self.x1 + 1

    @property
    def marks_end(self) -> float:
        return self.marks_x + len(self.marked) * (MARK_W + 1)

    @property
    def right(self) -> float:
        return max(self.x1, self.marks_end)

    def label_x(self, room_until: float) -> float | None:
        """Where the service name goes: inside the bar after its marks when it fits, else after
        the bar when there is room before `room_until` (the next bar of its row), else nowhere."""
        width = LABEL_CHAR_W * len(self.request.shown)
        inside = max(self.x0, self.marks_end) + 2
        if self.x1 - inside > width:
            return inside
        return self.right + 2 if self.right + 2 + width < room_until else None


def _pack(bars: list[Bar]) -> list[list[Bar]]:
    """Stack overlapping bars of one module into as few rows as possible (first fit)."""
    rows: list[list[Bar]] = []
    for bar in bars:
        row = next((row for row in rows if row[-1].right + 1 < bar.x0), None)
        if row is None:
            rows.append(row := [])
        row.append(bar)
    return rows


def _bar_title(r: RequestBar, verdicts: list[dict]) -> str:
    ended = ("no final reply before the trace ended" if r.end is None
             else f"final reply {r.reply!r} (class {r.reply_class or '?'}) at {r.end:.3f} s")
    lines = [f"#{r.rqst_id} {r.label()}", f"requested at {r.start:.3f} s, {ended}"]
    if r.state:
        lines.append(f"lifecycle state of {r.module} at the request: {r.state}")
    lines += [f"{v['verdict']} {v['property_id']}" for v in verdicts]
    return "\n".join(lines)


def _verdict_title(v: dict) -> str:
    margin = "" if v["margin_s"] is None else f", margin {v['margin_s']:.4f} s"
    flag = " - SUSPICIOUS: may be a false observation" if v["suspicious"] else ""
    return f"{v['verdict']} {v['property_id']} on #{v['rqst_id']}: C holds: {yes_no(v['c_holds']) or 'undecided'}{margin}{flag}"


def _world_title(w: dict) -> str:
    detail = json.loads(w["detail"]) if w["detail"] else {}
    words = ", ".join(f"{k}={v}" for k, v in detail.items())
    return f"{w['kind']} at {w['t']:.3f} s" + (f": {words}" if words else "")


def timeline(modules: list[str], requests: list[RequestBar], verdicts: list[dict], world: list[dict],
             end_t: float, outcome: str) -> Markup:
    """The trace's timeline; `modules` gives the lane order, `end_t` the end of the trace."""
    end_t = max([end_t, *(r.start if r.end is None else r.end for r in requests), *(w["t"] for w in world)]) or 1.0
    x = lambda t: LEFT + PLOT_W * t / end_t  # noqa: E731
    by_rqst: dict[int, list[dict]] = {}
    for v in verdicts:
        by_rqst.setdefault(v["rqst_id"], []).append(v)
    bars = [Bar(r, by_rqst.get(r.rqst_id, []), x(r.start),
                max(x(end_t if r.end is None else r.end), x(r.start) + MIN_BAR_W)) for r in requests]
    present = {r.module for r in requests}
    order = [m for m in modules if m in present] + sorted(present - set(modules))
    lanes = [(m, _pack([b for b in bars if b.request.module == m])) for m in order]
    height = AXIS_H + sum(len(rows) * ROW_H + 2 * LANE_PAD for _, rows in lanes) + ROW_H + 2 * LANE_PAD
    root = svg(LEFT + PLOT_W + RIGHT, height + 4, "timeline", f"timeline of {len(requests)} requests")
    _axis(root, x, end_t, height)
    y = AXIS_H
    for module, rows in lanes:
        lane_h = len(rows) * ROW_H + 2 * LANE_PAD
        lane = add(root, "g", css_class="lane", data_module=module)
        add(lane, "rect", css_class="lane-bg", x=0, y=y, width=LEFT + PLOT_W + RIGHT, height=lane_h)
        add(lane, "text", module, css_class="lane-label", x=6, y=y + lane_h / 2 + 4)
        for i, row in enumerate(rows):
            top = y + LANE_PAD + i * ROW_H + (ROW_H - BAR_H) / 2
            for bar, after in zip(row, row[1:] + [None]):
                _bar(lane, bar, top, LEFT + PLOT_W + RIGHT if after is None else after.x0)
        y += lane_h
    _world_lane(root, world, x, y, height)
    if outcome != "completed":
        add(root, "text", f"{outcome} at {end_t:g} s", css_class="trace-end-label", x=x(end_t),
            y=AXIS_H - 20, text_anchor="end")
    return markup(root)


def _axis(root, x, end_t: float, height: float) -> None:
    step = nice_step(end_t)
    axis = add(root, "g", css_class="axis")
    for i in range(int(end_t / step) + 1):
        tx = x(i * step)
        add(axis, "line", css_class="grid", x1=tx, x2=tx, y1=AXIS_H - 4, y2=height)
        add(axis, "text", f"{i * step:g} s", x=tx, y=AXIS_H - 8, text_anchor="middle")
    add(axis, "line", css_class="trace-end", x1=x(end_t), x2=x(end_t), y1=AXIS_H - 4, y2=height,
        title=f"end of the trace at {end_t:.3f} s")


def _bar(lane, bar: Bar, top: float, room_until: float) -> None:
    r = bar.request
    css = f"bar reply-{r.reply_class or 'unknown'}" if r.end is not None else "bar open"
    group = add(lane, "g", css_class="request", data_rqst=r.rqst_id)
    add(group, "rect", css_class=css, x=bar.x0, y=top, width=bar.x1 - bar.x0, height=BAR_H, rx=2,
        title=_bar_title(r, bar.verdicts))
    for k, v in enumerate(bar.marked):
        mx = bar.marks_x + k * (MARK_W + 1)
        css = f"verdict verdict-{v['verdict']}" + (" suspicious" if v["suspicious"] else "")
        mark = add(group, "g", css_class=css, data_property=v["property_id"])
        add(mark, "rect", x=mx, y=top, width=MARK_W, height=BAR_H, rx=3, title=_verdict_title(v))
        add(mark, "text", v["verdict"], css_class="mark-label", x=mx + MARK_W / 2, y=top + BAR_H - 3,
            text_anchor="middle")
    label_x = bar.label_x(room_until)
    if label_x is not None:
        add(group, "text", r.shown, css_class="bar-label", x=label_x, y=top + BAR_H - 2)


def _world_lane(root, world: list[dict], x, y: float, height: float) -> None:
    lane = add(root, "g", css_class="world-lane")
    lane_h = ROW_H + 2 * LANE_PAD
    add(lane, "rect", css_class="lane-bg", x=0, y=y, width=LEFT + PLOT_W + RIGHT, height=lane_h)
    add(lane, "text", "world", css_class="lane-label", x=6, y=y + lane_h / 2 + 4)
    if not world:
        add(lane, "text", "no world events", css_class="bar-label", x=LEFT + 4, y=y + lane_h / 2 + 4)
    for w in world:
        wx, cy = x(w["t"]), y + lane_h / 2
        event = add(lane, "g", css_class=f"world-event world-{w['kind']}")
        add(event, "line", x1=wx, x2=wx, y1=AXIS_H, y2=height)
        add(event, "path", d=f"M{wx:.1f},{cy - 6:.1f} l6,6 l-6,6 l-6,-6 z", title=_world_title(w))
