"""More properties than a mission has, for the bench's growth with their number: the Dala
properties repeated, each copy k (1, 2, ...) a property of its own id (`<id>#k`) with other
parameters: its x and y without their k-th service where they have more than one (each copy then
judges another set of requests, of the same type and about the same size)."""
from __future__ import annotations

from dataclasses import replace

from harness.target.interface import Property


def _without(services: tuple[str, ...], k: int) -> tuple[str, ...]:
    return services if len(services) < 2 else services[:k % len(services)] + services[k % len(services) + 1:]


def repeated(properties: list[Property], count: int) -> list[Property]:
    """`count` properties: the originals, then their copies, in order."""
    found = list(properties)
    k = 0
    while len(found) < count:
        k += 1
        found += [replace(p, id=f"{p.id}#{k}", x=_without(p.x, k), y=_without(p.y, k)) for p in properties]
    return found[:count]
