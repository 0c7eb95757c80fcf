"""A tiny SVG writer: elements as slotted objects serialised by one join, with every text and
attribute value escaped here (a report of thousands of timelines cannot afford ElementTree)."""
from __future__ import annotations

import math
import re
from html import escape

from markupsafe import Markup


class Element:
    __slots__ = ("tag", "attrs", "text", "children")

    def __init__(self, tag: str, attrs: str, text: str | None):
        self.tag, self.attrs, self.text, self.children = tag, attrs, text, []

    def write(self, out: list[str]) -> None:
        out.append(f"<{self.tag}{self.attrs}")
        if self.text is None and not self.children:
            out.append(" />")
            return
        out.append(">" if self.text is None else f">{text(self.text)}")
        for child in self.children:
            child.write(out)
        out.append(f"</{self.tag}>")


_NAMES: dict[str, str] = {"css_class": "class"}


def _attrs(attrs: dict) -> str:
    """`css_class` becomes class and underscores become dashes; None values are left out."""
    return "".join(f' {_NAMES.get(k) or _NAMES.setdefault(k, k.replace("_", "-"))}="{_value(v)}"'
                   for k, v in attrs.items() if v is not None)


def _value(v) -> str:
    if isinstance(v, float):
        return f"{v:.2f}".rstrip("0").rstrip(".")
    return text(v) if isinstance(v, str) else str(v)


_UNSAFE = re.compile(r"""[&<>"']""")


def text(value: str) -> str:
    """`value` escaped for HTML text or attributes; most values (names, classes) need nothing."""
    return escape(value) if _UNSAFE.search(value) else value


def svg(width: float, height: float, css_class: str, label: str) -> Element:
    return Element("svg", _attrs({"xmlns": "http://www.w3.org/2000/svg", "css_class": css_class,
                                  "width": width, "height": height, "role": "img",
                                  "viewBox": f"0 0 {_value(width)} {_value(height)}", "aria_label": label}), None)


def add(parent: Element, tag: str, text: str | None = None, title: str | None = None, **attrs) -> Element:
    """Append an element; a title becomes its <title> child, which browsers show as a tooltip."""
    element = Element(tag, _attrs(attrs), text)
    if title is not None:
        element.children.append(Element("title", "", title))
    parent.children.append(element)
    return element


def markup(root: Element) -> Markup:
    out: list[str] = []
    root.write(out)
    return Markup("".join(out))


def nice_step(span: float, ticks: int = 10) -> float:
    """A 1-2-5 step giving about `ticks` ticks over `span`."""
    if span <= 0:
        return 1.0
    raw = span / ticks
    power = 10 ** math.floor(math.log10(raw))
    return next(m * power for m in (1, 2, 5, 10) if m * power >= raw)

