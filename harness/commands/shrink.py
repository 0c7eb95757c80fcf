"""`untimely shrink TRACE`: a bad trace's script, reduced to the smallest showing the same bad behaviour."""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from harness import store
from harness.campaign import shrink
from harness.campaign.request import ShrinkRequest
from harness.commands import options
from harness.errors import UntimelyError
from harness.files import make_folder
from harness.sut.definitions import load_suts_file, resolve
from harness.sut.external.kept import kept_adapters
from harness.target.interface import load_properties
from harness.target.mission import PROPERTIES_FILE, SUTS_FILE

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
    orig = with_trusted_sut(shrink.original(con, request.trace_id, request.mission), request.sut,
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


def with_trusted_sut(orig: shrink.Original, sut_option: str | None, mission_given: bool,
                     confirmed: bool) -> shrink.Original:
    """The trace with the definition of its SUT that the user gave: --sut, else the suts.toml of
    the --mission folder; the one recorded in the store only if it runs no command or the user
    confirmed it."""
    if sut_option:
        names, external = resolve(sut_option, orig.mission)
        if orig.sut not in names:
            raise UntimelyError(f"--sut {sut_option!r} does not name trace {orig.trace_id}'s SUT {orig.sut!r}; "
                                f"give --sut {orig.sut} (with =cmd:COMMAND or =tcp://HOST:PORT if it is external)")
        return replace(orig, external={n: s for n, s in external.items() if n == orig.sut})
    defined = load_suts_file(orig.mission / SUTS_FILE) if mission_given else {}
    if orig.sut in defined:
        return replace(orig, external={orig.sut: defined[orig.sut]})
    command = orig.external[orig.sut].command if orig.sut in orig.external else None
    if command and not confirmed:
        raise UntimelyError(f"trace {orig.trace_id} ran on {orig.sut!r}, whose command the store records as "
                            f"{command!r}; shrink does not run a command read from a store: name the SUT "
                            f"again with --sut {orig.sut}=cmd:COMMAND, or --mission FOLDER whose suts.toml "
                            f"defines {orig.sut!r}, or pass --run-stored-command if you trust this store")
    return orig
