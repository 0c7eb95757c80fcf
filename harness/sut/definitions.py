"""Which systems a run or campaign tests, as `--sut` and `suts.toml` name them: simulator
variants, or external SUTs over `untimely/1` (their description: harness.target.suts).

`--sut` takes comma-separated entries, each one of
- a variant of the in-process simulated layer (`genom`, `reference`, ...),
- `NAME=cmd:COMMAND`: an adapter the bench starts for every run and talks to on stdio,
- `NAME=tcp://HOST:PORT`: an adapter already listening, reached anew for every run,
- a name defined in the mission folder's `suts.toml`, where a SUT also gets its environment,
  slots (how many may run at once) and time scale; its command starts in that folder, so it
  may name the adapter relative to it.
In a command, `{python}` is the bench's own interpreter, `{root}` the folder holding the
harness package (the repository in a checkout) and, in suts.toml, `{mission}` the mission folder.
"""
from __future__ import annotations

import re
import shlex
from pathlib import Path

from harness.errors import InputFileError, UntimelyError
from harness.files import read_toml
from harness.schema import cut, validated, where
from harness.target.mission import SUTS_FILE
from harness.target.suts import TRANSPORTS, ExternalSut, SutTable

NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")


def _checked(name: str, spec, path, text: str | None = None) -> ExternalSut:
    """An ExternalSut from a table of values read from `path` (a file, or the --sut option)."""
    table = validated(SutTable, spec, path, text, at=(name,) if text is not None else ())
    return ExternalSut(name, **table.model_dump())


def load_suts_file(path: Path) -> dict[str, ExternalSut]:
    if not path.exists():
        return {}
    data, text = read_toml(path)
    suts = {}
    for name, spec in data.items():
        if not NAME.fullmatch(name) or not isinstance(spec, dict):
            raise InputFileError(path, where(text, (name,)), f"{cut(name)}: a SUT is a table named by letters, "
                                 "digits, '_', '.' or '-'")
        if isinstance(spec.get("command"), str):
            spec = {**spec, "command": spec["command"].replace("{mission}", shlex.quote(str(path.parent.resolve())))}
        sut = _checked(name, spec, path, text)
        suts[name] = sut.model_copy(update={"cwd": str(path.parent.resolve())}) if sut.command else sut
    return suts


def resolve(option: str, mission: Path, time_scale: float | None = None) -> tuple[list[str], dict[str, ExternalSut]]:
    """The SUT names of a `--sut` option, in order, and the external ones' definitions;
    `time_scale` (the --time-scale option) overrides the definitions' own."""
    names, external = [], {}
    defined = load_suts_file(mission / SUTS_FILE)
    for entry in (e.strip() for e in option.split(",")):
        name, _, target = entry.partition("=")
        if not NAME.fullmatch(name) or name in names:
            raise UntimelyError(f"--sut {option!r}: {entry!r} is not a new SUT name; give distinct "
                                "comma-separated entries, e.g. genom,bip-a or toy=cmd:COMMAND")
        if target:
            scheme = next((s for s in TRANSPORTS if target.startswith(s)), None)
            if scheme is None:
                raise UntimelyError(f"--sut {entry!r}: write NAME=cmd:COMMAND or NAME=tcp://HOST:PORT")
            external[name] = _checked(name, {TRANSPORTS[scheme][0]: target[len(scheme):]}, f"--sut {entry!r}")
        elif name in defined:
            external[name] = defined[name]
        names.append(name)
    if time_scale is not None:  # checked > 0 by the command line
        external = {n: s.model_copy(update={"time_scale": time_scale}) for n, s in external.items()}
    return names, external
