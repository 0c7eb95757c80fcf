"""Delta debugging (Zeller's ddmin): a 1-minimal sublist that still passes a test.

`test(sublist)` says whether the sublist still shows what we look for; the order of the items
is kept. 1-minimal: removing any single item makes the test fail.
"""
from __future__ import annotations

from typing import Callable, Sequence


def ddmin(items: Sequence, test: Callable[[list], bool]) -> list:
    items, n = list(items), 2
    while len(items) >= 2:
        size = -(-len(items) // n)  # ceil
        chunks = [items[i:i + size] for i in range(0, len(items), size)]
        for i, chunk in enumerate(chunks):
            if test(chunk):
                items, n = chunk, 2
                break
            complement = [x for j, c in enumerate(chunks) if j != i for x in c]
            if len(chunks) > 2 and test(complement):
                items, n = complement, max(n - 1, 2)
                break
        else:
            if n >= len(items):
                return items
            n = min(len(items), 2 * n)
    return items
