"""`untimely shrink TRACE`: a bad trace's script, reduced to the smallest showing the same bad behaviour."""
from __future__ import annotations

from pathlib import Path

from harness import store
from harness.campaign import shrink
from harness.campaign.request import ShrinkRequest
from harness.commands import options
from harness.errors import UntimelyError
from harness.files import make_folder
from harness.sut.external.kept import kept_adapters
from harness.target.interface import load_properties
from harness.target.mission import PROPERTIES_FILE

NAME = "shrink"
HELP = "reduce a bad trace's script to the smallest one showing the same bad behaviour"
Request = ShrinkRequest


def arguments(c) -> None:
    c.add_argument("trace_id", type=int, help="a hung trace, or one with an FN or FP verdict")
    c.add_argument("--property", help="shrink the FN (else FP) on this property id (default: the hang, "
                                      "else the trace's first FN or FP)")
    c.add_argument("--verdict", choices=("FN", "FP"), help="with --property: keep this verdict (default: FN, else FP)")
    c.add_argument("--mission", help="mission folder (default: the trace's campaign's); its suts.toml "
                                     "may define the trace's external SUT")
    c.add_argument("--sut", help="the trace's SUT, named again: an external SUT's command is never "
                                 f"read from the store{options.EXTERNAL_HELP}")
    c.add_argument("--run-stored-command", action="store_true",
                   help="run the external SUT's command recorded in the store (only for a store you trust)")
    c.add_argument("--out", help="folder of the .mission file (default: shrunk/ beside the store)")
    options.db(c)


def execute(request: ShrinkRequest) -> int:
    out = make_folder(Path(request.out) if request.out else shrink.default_out(request.db),
                      "the shrunk scripts")  # before the work
    con = store.connect(request.db, create=False)
    orig = shrink.with_trusted_sut(shrink.original(con, request.trace_id, request.mission), request.sut,
                                   bool(request.mission), request.run_stored_command)
    properties = load_properties(orig.mission / PROPERTIES_FILE, orig.interface)
    if request.verdict and not request.property:
        raise UntimelyError(f"--verdict {request.verdict} needs --property: the property whose verdict to keep")
    behaviour = shrink.behaviour_of(orig, properties, request.property, request.verdict)
    with kept_adapters():
        try:
            result = shrink.shrunk(orig, behaviour, properties)
        except KeyboardInterrupt:  # Ctrl-C or a stop signal: the runs made are stored all the same
            shrink.store_interrupted(con, orig, behaviour)
            raise
    line = shrink.stored(con, behaviour, result, out)  # its runs, even if it failed
    if result.error:
        raise UntimelyError(result.error)
    print(line)
    return 0
