"""The `untimely/1` wire format (docs/reference/protocol.md): one JSON object per line, each with an `op`.

Shared by the bench's side and the adapters the project ships, so both read and write the
same lines. A line that breaks the format raises ProtocolViolation, quoting what was wrong.
"""
from __future__ import annotations

import json
import math

from harness.errors import InternalSignal

PROTO = "untimely/1"
# What the SUT may send, with the fields each must carry and their JSON types.
SUT_MESSAGES = {
    "hello": {"proto": str},
    "reply": {"id": int, "kind": str},  # and `code`: text on a final, optional on the others
    "pong": {"id": int},
    "internal": {"id": int, "kind": str, "t": float},
    "world": {"t": float, "kind": str, "detail": dict},
    "error": {"message": str},
}
BENCH_MESSAGES = {
    "hello": {"proto": str, "run": int, "seed": int, "time_scale": float, "interface": dict},
    "request": {"id": int, "module": str, "service": str, "args": dict},
    "ping": {"id": int},
    "bye": {},
}
# A SUT that offered `reuse` in its hello answers the bench's bye with its own: the run is over on
# its side (nothing of it follows), and it takes the next run's hello (docs/protocol.md).
REUSE = "reuse"
SUT_FAREWELL = {"bye": {}}
# `taken`: the layer has taken the request (an optional reply of every request, at the instant its
# control task takes it; the oracles then place the request there, docs/protocol.md)
REPLY_KINDS = ("taken", "intermediate", "final")
INTERNAL_KINDS = ("request", "intermediate", "final")


class ProtocolViolation(InternalSignal):
    """A line that is not a well-formed message of the protocol."""


def encode(op: str, **fields) -> str:
    """One message as a line (NaN and infinities are refused: they are not JSON)."""
    return json.dumps({"op": op, **fields}, separators=(",", ":"), allow_nan=False) + "\n"


def has_type(value, kind: type) -> bool:
    """Whether a field's value is of the JSON type `kind` (a float: any finite number; no bool is a number)."""
    if kind is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if kind is int:
        return isinstance(value, int) and not isinstance(value, bool)
    return isinstance(value, kind)


def decode(line: str, messages: dict[str, dict[str, type]] = SUT_MESSAGES) -> dict:
    """The message of one line, checked against `messages` (what the other side may send)."""
    try:
        message = _DECODER.decode(line)
    except ValueError as e:
        raise ProtocolViolation(f"not a JSON line ({e})") from None
    except RecursionError:
        raise ProtocolViolation("JSON nested too deeply to read") from None
    if not isinstance(message, dict):
        raise ProtocolViolation("not a JSON object")
    op = message.get("op")
    if op not in messages:
        raise ProtocolViolation(f"unknown op {op!r}; expected one of {', '.join(messages)}")
    for name, kind in messages[op].items():
        if not has_type(message.get(name), kind):
            raise ProtocolViolation(f"{op!r} needs a field {name!r} of type {kind.__name__}, "
                                    f"got {message.get(name)!r}")
    return message


def _refuse_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


_DECODER = json.JSONDecoder(parse_constant=_refuse_constant)  # one for all lines: making one costs
