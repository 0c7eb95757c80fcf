"""The command line of the Dala nodes (ROS 1 and ROS 2): the variant, the time scale, the mission
folder and the mapping file beside its interface."""
from __future__ import annotations

import argparse
import os
from pathlib import Path

from harness import DEFAULT_MISSION_DIR


def dala_arguments(argv: list[str] | None, description: str, mapping_name: str) -> argparse.Namespace:
    """The parsed arguments; `mapping` defaults to the mission folder's `mapping_name`."""
    parser = argparse.ArgumentParser(prog="dala_node", description=description)
    parser.add_argument("--variant", required=True,
                        help="a variant of the mission folder's layer.toml "
                             "(Dala: genom, bip-a, bip-b, bare, reference)")
    parser.add_argument("--time-scale", type=float, default=float(os.environ.get("UNTIMELY_TIME_SCALE", "1")),
                        help="mission seconds per wall second (default: $UNTIMELY_TIME_SCALE, else 1)")
    parser.add_argument("--mission", type=Path, default=DEFAULT_MISSION_DIR,
                        help=f"folder of interface.toml, world.toml and {mapping_name}")
    parser.add_argument("--mapping", type=Path, help=f"the mapping file (default: the mission folder's {mapping_name})")
    args = parser.parse_args(argv)
    args.mapping = args.mapping or args.mission / mapping_name
    return args
