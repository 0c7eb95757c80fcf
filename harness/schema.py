"""One schema layer for every input file: a pydantic model per file checks its keys, types and values.

A refusal names the file, the line of the offending key (when the TOML text shows it), the key's
path, its value (cut, so a megabyte is not echoed whole) and what to give instead: the field's
`description` when it has one, else pydantic's own wording. A model's `title` says what one of its
tables is ("a service"), for the message that lists the keys such a table takes.
"""
from __future__ import annotations

import re
import types
import typing

from pydantic import BaseModel, ConfigDict, ValidationError

from harness.errors import InputFileError

SHOWN_CHARS = 80  # of a bad value, in a message


class Strict(BaseModel):
    """A table of an input file: no unknown key, no type conversion, no NaN or infinity."""
    model_config = ConfigDict(strict=True, extra="forbid", allow_inf_nan=False, frozen=True)


def cut(value, limit: int = SHOWN_CHARS) -> str:
    """The repr of `value`, cut to `limit` characters."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text):,} characters)"


def validated(model: type[BaseModel], data, path, text: str | None = None, at: tuple = ()):
    """`data` (read from `path`, whose TOML `text` gives lines; the table at keys `at` of it) as a
    `model`, or an InputFileError."""
    try:
        return model.model_validate(data)
    except ValidationError as e:
        error = e.errors(include_url=False)[0]
        keys, field, table = _resolve(model, error["loc"])
        error["loc"] = at + error["loc"]
        keys = at + keys
        raise InputFileError(path, where(text, keys), _problem(error, keys, field, table)) from None


def where(text: str | None, keys: tuple) -> str:
    """The line of the deepest key of `keys` the text shows ("" when none: the message names the key)."""
    line = line_of(text, keys) if text is not None else None
    return str(line) if line else ""


def dotted(keys: tuple) -> str:
    """Keys as a TOML user reads them: `modules.m.services`, `rock[1].radius` (items counted from 1)."""
    return "".join(f"[{k + 1}]" if isinstance(k, int) else f".{k}" for k in keys).lstrip(".")


def _problem(error: dict, keys: tuple, field, table) -> str:
    name, kind = dotted(keys) or "the file", error["type"]
    if kind == "extra_forbidden":
        title = table.model_config.get("title") or "this table"
        return f"unknown key {cut(keys[-1])}; {title} takes {', '.join(accepted(table))}"
    if kind == "value_error":  # a model's own check: its message names the value
        return f"{dotted(keys)}: {error['ctx']['error']}" if keys else str(error["ctx"]["error"])
    hint = field.description if field is not None and field.description else _reworded(error)
    if error["loc"][-1] == "[key]":  # a table's key, not its value, is refused
        return f"{dotted(keys[:-1])}: key {cut(error['input'])} is not allowed; {hint}"
    if kind == "missing":
        return f"{name} is missing; {hint}"
    return f"{name} = {cut(error['input'])}; {hint}"


def accepted(table: type[BaseModel]) -> tuple[str, ...]:
    """The keys a table of this model accepts, as the file spells them."""
    return tuple(f.alias or n for n, f in table.model_fields.items())


REWORDED = {"dict_type": "give a table", "model_type": "give a table", "list_type": "give a list [...]", "bool_type": "give true or false",
            "finite_number": "give a finite number", "string_too_short": "give a non-empty string"}


def _reworded(error: dict) -> str:
    if error["type"] in REWORDED:
        return REWORDED[error["type"]]
    if error["type"] in ("union_tag_invalid", "union_tag_not_found"):
        return f"give {error['ctx']['discriminator']} = {error['ctx']['expected_tags']}"
    if error["type"] in ("greater_than", "greater_than_equal"):
        sign = ">" if error["type"] == "greater_than" else ">="
        return f"give a number {sign} {next(iter(error['ctx'].values()))}"
    message = error["msg"]
    return "give " + message[len("Input should be "):] if message.startswith("Input should be ") else message


def _resolve(model: type[BaseModel], loc: tuple) -> tuple[tuple, object, type[BaseModel]]:
    """The keys of `loc` as the file spells them (pydantic's tag and validator steps left out), the
    field they end in (None for a dict key or list item) and the model of the table holding it."""
    keys, field, current, table = [], None, model, model
    for part in loc:
        current = _unwrapped(current, part)
        if isinstance(current, type) and issubclass(current, BaseModel):
            table = current
            match = next((f for n, f in current.model_fields.items() if part in (n, f.alias)), None)
            if match is None:
                if part not in _tags(current):
                    keys.append(part)  # an unknown key
                continue
            keys.append(part)
            field, current = match, match.annotation
            continue
        origin = typing.get_origin(current)
        if origin is dict or origin is list or origin is tuple:
            keys.append(part)
            field, current = None, typing.get_args(current)[-1 if origin is dict else 0]
    return tuple(keys), field, table


def _unwrapped(annotation, part):
    """The member of a union (or Annotated type) that a location's next `part` goes into."""
    while True:
        origin = typing.get_origin(annotation)
        if origin is typing.Annotated:
            annotation = typing.get_args(annotation)[0]
        elif origin is typing.Union or origin is types.UnionType:
            members = [a for a in typing.get_args(annotation) if a is not type(None)]
            models = [m for m in members if isinstance(m, type) and issubclass(m, BaseModel)]
            annotation = next((m for m in models if part in _tags(m) or part in m.model_fields),
                              models[0] if models else members[0])
        else:
            return annotation


def _tags(model: type[BaseModel]) -> set:
    """The values of the model's literal fields: pydantic names a tagged union's member by them."""
    return {v for f in model.model_fields.values() if typing.get_origin(f.annotation) is typing.Literal
            for v in typing.get_args(f.annotation)}


KEY = r'(?:[A-Za-z0-9_-]+|"[^"]*"|\'[^\']*\')'
HEADER = re.compile(rf"\s*\[(\[?)\s*({KEY}(?:\s*\.\s*{KEY})*)\s*\]\]?\s*(?:#.*)?$")
ASSIGNMENT = re.compile(rf"\s*({KEY}(?:\s*\.\s*{KEY})*)\s*=")


def _split(keys: str) -> list[str]:
    return [k.strip().strip("\"'") for k in re.findall(rf"{KEY}", keys)]


def line_of(text: str, loc: tuple) -> int | None:
    """The line of `text` (TOML) that holds the deepest key of `loc` it shows; only `\n` ends a line."""
    table, arrays, best, best_depth = [], {}, None, 0
    for n, line in enumerate(text.split("\n"), 1):
        header = HEADER.match(line)
        if header:
            table = _split(header[2])
            if header[1]:  # [[array]]: its n-th table is item n - 1
                arrays[tuple(table)] = arrays.get(tuple(table), -1) + 1
                table = table + [arrays[tuple(table)]]
            path = table
        else:
            assignment = ASSIGNMENT.match(line)
            if not assignment:
                continue
            path = table + _split(assignment[1])
        depth = len(path) if list(loc[:len(path)]) == path else 0
        if depth > best_depth:
            best, best_depth = n, depth
    return best
