"""A small interface with an action and its cancel (arm.move, arm.move_cancel), one without
(arm.home) and a control service: the tests of the mission language's `cancel` step."""
from pathlib import Path

from harness.target.interface import Interface, load_interface

ARM = """[replies]
ok = "T"
canceled = "Z"
rejected = "R"

[modules.arm]
services.move = { kind = "exec", args = { order = { type = "float" } } }
services.move_cancel = { kind = "control" }
services.home = { kind = "exec" }
services.grip = { kind = "control" }
"""


def arm_interface(folder: Path) -> Interface:
    """The interface, written to `folder`/interface.toml and loaded."""
    (folder / "interface.toml").write_text(ARM)
    return load_interface(folder / "interface.toml")
