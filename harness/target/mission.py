"""A target is a folder under missions/: one loader reads it, its files, their hashes, its defaults.

| file | holds | needed |
| --- | --- | --- |
| `interface.toml` | modules, services, reply catalogue (the tester's black-box view) | yes |
| `golden.mission` | the golden script | yes |
| `properties.toml` | the properties the oracles judge | to analyze |
| `layer.toml` | the simulated layer's own knowledge: protections, defects, variants | to simulate |
| `world.toml` | the world the layer's behaviour module builds, if it needs one | no |
| `suts.toml` | external systems under test | no |
| `ros.toml`, `ros2.toml` | how the interface appears on ROS 1, ROS 2 (the adapters' and bags' mapping) | no |

These names are this module's (`*_FILE`): the rest of the bench uses them, never their text
(tests/project/test_layout.py checks it).

A trace depends on the golden script, the interface, the layer description and the world (not on
the properties: editing a property re-judges traces, it does not re-run them): their hashes are a
campaign's identity, an absent optional file hashed as absent.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

from harness.errors import InputFileError
from harness.files import read_bytes
from harness.target.interface import Interface, Property, load_interface, load_properties
from harness.target.script import Script, load_script
from harness.target.layer_description import LayerDescription, load_layer_file

INTERFACE_FILE = "interface.toml"
LAYER_FILE = "layer.toml"
GOLDEN_FILE = "golden.mission"
PROPERTIES_FILE = "properties.toml"
WORLD_FILE = "world.toml"
SUTS_FILE = "suts.toml"
ROS_MAPPING_FILE = "ros.toml"
ROS2_MAPPING_FILE = "ros2.toml"
REQUIRED = (GOLDEN_FILE, INTERFACE_FILE)
TRACE_FILES = REQUIRED + (LAYER_FILE, WORLD_FILE)


def load_layer(folder: Path) -> LayerDescription:
    """The layer description of a mission folder (its LAYER_FILE), read once per file version."""
    return load_layer_file(Path(folder) / LAYER_FILE)


@dataclass(frozen=True)
class Mission:
    folder: Path
    interface: Interface

    @property
    def interface_file(self) -> Path:
        return self.folder / INTERFACE_FILE

    @property
    def golden_file(self) -> Path:
        return self.folder / GOLDEN_FILE

    @property
    def properties_file(self) -> Path:
        return self.folder / PROPERTIES_FILE

    @property
    def world_file(self) -> Path:
        """The world the layer is built on; the path stands for the folder when there is none."""
        return self.folder / WORLD_FILE

    @property
    def simulated(self) -> bool:
        return (self.folder / LAYER_FILE).exists()

    @property
    def layer(self) -> LayerDescription:
        return load_layer(self.folder)

    def golden(self) -> Script:
        return load_script(self.golden_file, self.interface)

    def properties(self) -> list[Property]:
        return load_properties(self.properties_file, self.interface)

    def default_suts(self) -> str:
        """A campaign's --sut when none is given: the layer's default variants."""
        if not self.simulated:
            raise InputFileError(self.folder / LAYER_FILE, "", "file not found; a folder without a simulated "
                                 "layer needs --sut NAME=cmd:COMMAND or a NAME from its suts.toml")
        return ",".join(self.layer.default_suts)

    def hashes(self) -> dict[str, str | None]:
        return {name: _sha256(self.folder / name, name in REQUIRED) for name in TRACE_FILES}


# what a file of the mission folder that is not there is told as
MISSING = "file not found; a mission folder holds " + ", ".join(REQUIRED) + " (and properties.toml, layer.toml, world.toml)"


def _sha256(path: Path, required: bool) -> str | None:
    if not required and not path.exists() and not path.is_symlink():
        return None
    return hashlib.sha256(read_bytes(path, MISSING)).hexdigest()


def load_mission(folder: str | Path) -> Mission:
    folder = Path(folder)
    if not folder.is_dir():
        raise InputFileError(folder, "", "not a folder; give a mission folder such as missions/dala")
    return Mission(folder, load_interface(folder / INTERFACE_FILE))
