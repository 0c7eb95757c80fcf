"""A tiny SVG writer on ElementTree: escaping is ElementTree's job, never ours."""
from __future__ import annotations

import math
from xml.etree import ElementTree as ET

from markupsafe import Markup


def svg(width: float, height: float, css_class: str, label: str) -> ET.Element:
    return ET.Element("svg", {"xmlns": "http://www.w3.org/2000/svg", "class": css_class,
                              "width": _num(width), "height": _num(height), "role": "img",
                              "viewBox": f"0 0 {_num(width)} {_num(height)}", "aria-label": label})


def add(parent: ET.Element, tag: str, text: str | None = None, title: str | None = None,
        **attrs) -> ET.Element:
    """Append an element; `css_class` becomes class and underscores become dashes."""
    names = {"css_class": "class"}
    element = ET.SubElement(parent, tag, {names.get(k, k.replace("_", "-")): _num(v)
                                          for k, v in attrs.items() if v is not None})
    element.text = text
    if title is not None:  # browsers show an element's <title> child as its tooltip
        ET.SubElement(element, "title").text = title
    return element


def markup(root: ET.Element) -> Markup:
    return Markup(ET.tostring(root, encoding="unicode", short_empty_elements=True))


def nice_step(span: float, ticks: int = 10) -> float:
    """A 1-2-5 step giving about `ticks` ticks over `span`."""
    if span <= 0:
        return 1.0
    raw = span / ticks
    power = 10 ** math.floor(math.log10(raw))
    return next(m * power for m in (1, 2, 5, 10) if m * power >= raw)


def _num(value) -> str:
    if isinstance(value, float):
        return f"{value:.2f}".rstrip("0").rstrip(".")
    return str(value)
