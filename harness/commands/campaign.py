"""`untimely campaign`: golden + mutants on each SUT, resumable (docs/campaigns.md)."""
from __future__ import annotations

from harness.campaign import campaign
from harness.campaign.request import CampaignRequest
from harness.commands import options
from harness.mutator.operators import OPERATORS, REQUEST_OPERATORS

NAME = "campaign"
HELP = "run golden + seeded mutants on each variant; resumable"
Request = CampaignRequest


def arguments(c) -> None:
    c.add_argument("--mission", default=Request.mission, help="mission folder (default: %(default)s)")
    c.add_argument("--mutants", type=int, default=Request.mutants, help="number of mutants (default: %(default)s)")
    c.add_argument("--sut", help="comma-separated SUTs (default: the layer.toml's default_suts): "
                   f"variants {options.variants_help()}{options.EXTERNAL_HELP}")
    c.add_argument("--seed", type=options.SEED, default=Request.seed, help="campaign seed (default: %(default)s)")
    c.add_argument("--jobs", type=options.JOBS, default=Request.jobs,
                   help=f"worker processes, 0 = all cores, at most {options.MAX_JOBS} (default: %(default)s)")
    c.add_argument("--strategy", choices=("random", "targeted", "focused"), default=Request.strategy,
                   help="random: the paper's operators; targeted: mutants aimed at falsifying the "
                        "least-covered properties' conditions; focused: short tests, one per way to "
                        "falsify a condition, until the campaign decides it is done (default: %(default)s)")
    c.add_argument("--budget", metavar="DURATION",
                   help="focused only: the mission time all runs may take, shrink runs included "
                        "(4000s, 40m, 1h; default: none, the stopping rule ends the campaign)")
    c.add_argument("--ops-per-mutant", type=options.COUNT, default=None,
                   help="mutation operations per mutant (default: 1 random, 3 targeted)")
    c.add_argument("--shrink", action="store_true",
                   help="then shrink one representative trace of each distinct bad behaviour "
                        "(focused: each new finding as it shows, within the budget)")
    c.add_argument("--time-mutations", action="store_true", help="also drop waits and change sleeps")
    c.add_argument("--value-mutations", action="store_true",
                   help="also give arguments exceptional values (bounds, beyond them, nan, wrong types, ...); "
                        "targeted and focused: also aim at the value-domain properties")
    c.add_argument("--operators", metavar="A,B", help="the mutation operators random mutants draw among, of "
                   f"{', '.join(OPERATORS)} (default: the paper's three, {', '.join(REQUEST_OPERATORS)})")
    c.add_argument("--cluster", metavar="ADDRESS", type=options.CLUSTER,
                   help="run on a Dask cluster: a scheduler address (tcp://HOST:8786) or local:N for N local "
                        "workers; needs the cluster extra (docs/cluster.md)")
    c.add_argument("--max-delay", type=options.SECONDS, default=Request.max_delay,
                   help="largest interface observation delay in seconds (default: %(default)s)")
    c.add_argument("--shard", metavar="I/N", help="run only the I-th of N disjoint parts of the campaign "
                   "(1 <= I <= N) into this store; `merge` combines the N stores (docs/ci.md)")
    c.add_argument("--allow-code-change", action="store_true",
                   help="resume a campaign that another version of the bench's code made (its traces then "
                        "mix runs of both; refused without it)")
    options.time_scale(c)
    options.rosbag(c)
    options.db(c)


def execute(request: CampaignRequest) -> int:
    return campaign.main(request)
