"""`untimely run MISSION --sut NAME`: one script on one SUT, stored and summarised."""
from __future__ import annotations

from harness.campaign import adhoc
from harness.campaign.request import RunRequest
from harness.commands import options

NAME = "run"
HELP = "run one script on one variant, store and summarise its trace"
Request = RunRequest


def arguments(c) -> None:
    c.add_argument("script", metavar="MISSION", help="a mission script, e.g. missions/dala/golden.mission")
    c.add_argument("--sut", required=True,
                   help=f"implementation variant: {options.variants_help()}{options.EXTERNAL_HELP}")
    c.add_argument("--seed", type=options.SEED, default=Request.seed,
                   help="seed of the observation delays (default: %(default)s)")
    c.add_argument("--interface", help="interface description (default: interface.toml beside the script)")
    c.add_argument("--world", help="world description (default: world.toml beside the --interface given, "
                                    "else beside the script)")
    c.add_argument("--max-delay", type=options.SECONDS, default=Request.max_delay,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    options.time_scale(c)
    options.rosbag(c)
    options.db(c)


def execute(request: RunRequest) -> int:
    return adhoc.run(request)
