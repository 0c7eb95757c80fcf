"""What a SUT is, as a run describes it: a variant of the simulated layer, or an external SUT
reached over `untimely/1`, defined by a table of `suts.toml` or a `--sut NAME=URL`
(harness.sut.definitions reads both). Here, below the store that records them (campaigns.config)
and the transports that run them.
"""
from __future__ import annotations

import shlex
import sys

from pydantic import ConfigDict, Field, model_validator

from harness import ROOT, current_modules
from harness.schema import Strict, accepted, cut

# The transports, by the URL scheme of `--sut NAME=URL`: the key of a SUT's definition that the
# rest of the URL fills (suts.toml writes the same key), and what it reaches.
TRANSPORTS = {"cmd:": ("command", "stdio"), "tcp://": ("address", "tcp HOST:PORT")}


class SutTable(Strict):
    model_config = ConfigDict(title="a SUT")
    command: str | None = Field(None, description="give the adapter's command line")
    address: str | None = Field(None, pattern=r"^[^:\s]+:\d+$", description="give HOST:PORT, e.g. 127.0.0.1:7400")
    env: dict[str, str] = Field({}, description="give a table of NAME = \"text\"")
    slots: int = Field(1, gt=0, description="give a whole number > 0")
    time_scale: float = Field(1.0, gt=0, description="give a number > 0 (mission seconds per wall second)")
    startup_s: float = Field(30.0, gt=0, description="give a number of wall seconds > 0")
    probe_timeout_s: float = Field(3.0, gt=0, description="give a number of wall seconds > 0")

    @model_validator(mode="after")
    def _one_transport(self):
        if sum(getattr(self, key) is not None for key, _ in TRANSPORTS.values()) != 1:
            raise ValueError("give exactly one of " + " or ".join(f"{key} ({what})" for key, what in TRANSPORTS.values()))
        if self.command is not None:
            try:
                words = shlex.split(self.command)
            except ValueError as e:  # an unclosed quote
                raise ValueError(f"command = {cut(self.command)}: {e}; close the quote") from None
            if not words:
                raise ValueError("command is empty: give the adapter's command line")
        return self


class ExternalSut(SutTable):
    """A SUT reached over `untimely/1`: a table of `suts.toml` (or a `--sut NAME=URL`) with its name,
    and the folder its command starts in; the fields and their defaults are SutTable's."""
    # Not strict: it is also rebuilt from the JSON of campaigns.config, where a number may be an int.
    model_config = ConfigDict(title="a SUT", strict=False)
    name: str
    cwd: str | None = None  # where the command starts: the target folder of a suts.toml entry

    def __init__(self, name: str | None = None, /, **fields):
        # ExternalSut("toy", command=...) reads as the dataclass it was; a stored config gives name=.
        super().__init__(**fields if name is None else {"name": name, **fields})

    def argv(self) -> list[str]:
        """The command's words, placeholders filled in; a module it names by a name from before
        harness/sut/ runs under its current name (a store's recorded command, an older suts.toml)."""
        return [part.replace("{python}", sys.executable).replace("{root}", str(ROOT))
                for part in shlex.split(current_modules(self.command))]


KEYS = accepted(SutTable)  # the keys of a SUT's table (docs/reference names every one)
