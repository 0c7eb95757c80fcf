"""`python -m harness run MISSION --sut NAME`: one script on one variant, stored and summarised.

Each `run` is stored as a campaign of its own (config kind "run") holding one script and one
trace, so ad-hoc runs and campaigns can share a store without mixing.
"""
from __future__ import annotations

from collections import Counter
from pathlib import Path

from harness import store
from harness.campaign.request import RunRequest
from harness.errors import UntimelyError
from harness.sut.executive import run_script
from harness.files import existing_file
from harness.dispatch import transport
from harness.target.interface import load_interface
from harness.target.mission import INTERFACE_FILE, LAYER_FILE, WORLD_FILE
from harness.target.script import load_script
from harness.sut.definitions import resolve
from harness.store.record import RunRecord
from harness.trace import Trace
from harness.textable import real_time_factor


def mission_files(script_path: Path, interface: str | None = None, world: str | None = None) -> tuple[Path, Path]:
    """The interface and world descriptions: those given, else those of the target folder, the one of
    the interface given (a shrunk reproducer's replay names it), else the mission script's."""
    interface_path = Path(interface) if interface else script_path.resolve().parent / INTERFACE_FILE
    return interface_path, Path(world) if world else interface_path.parent / WORLD_FILE


def _world_given(world: str | None, world_file: Path, simulated: bool) -> None:
    """A --world that names nothing a simulated run can use (no such file, no layer.toml beside it:
    a target without a world is named by a path in its folder) is refused as the user gave it, not
    as the layer.toml beside it."""
    if world is not None and simulated and not world_file.is_file() and not (world_file.parent / LAYER_FILE).is_file():
        existing_file(world, f"world file not found, and no {LAYER_FILE} beside it; pass the world.toml of a "
                             "simulated target, or a path in the folder of its layer.toml")


def latency_line(provenance: dict) -> str:
    """The ping round trips of a real-time run (`analyze` suggests an epsilon from them)."""
    p = provenance
    if not p["pings"]:
        return "no ping answered: no latency measured"
    return (f"{p['pings']} pings on {p['host']}, round trip p50 {p['rtt_p50_s'] * 1000:.2f} ms, "
            f"p95 {p['rtt_p95_s'] * 1000:.2f} ms, max {p['rtt_max_s'] * 1000:.2f} ms (wall)")


def summary(trace: Trace, replies: dict[str, str]) -> str:
    requests = sum(1 for e in trace.events if e[2] == "request")
    finals = Counter(e[7] for e in trace.events if e[2] == "final")
    by_class = Counter()
    for code, n in finals.items():
        by_class[replies[code]] += n
    lines = [
        f"outcome    {trace.outcome}" + (f"  ({trace.error})" if trace.error else ""),
        f"requests   {requests}, final replies {sum(finals.values())}, "
        f"without final reply {requests - sum(finals.values())}",
        "replies    " + ", ".join(f"{cls} {by_class[cls]}" for cls in "TZR")
        + "  (" + ", ".join(f"{code} {n}" for code, n in sorted(finals.items())) + ")",
        f"world      {len(trace.world_events)} event(s)"
        + "".join(f"\n             t={t:.3f} {kind} {detail}" for t, kind, detail in trace.world_events),
        f"time       simulated {trace.sim_s:.1f} s, wall {trace.wall_s:.3f} s "
        f"({real_time_factor(trace.sim_s, trace.wall_s)} real time)",
    ]
    if trace.provenance:
        lines.append("interface  " + latency_line(trace.provenance))
    return "\n".join(lines)


def run(args: RunRequest) -> int:
    script_path = existing_file(args.script, "file not found; run takes a mission script such as "
                                              "missions/dala/golden.mission")
    interface_path, world_file = mission_files(script_path, args.interface, args.world)
    interface = load_interface(interface_path)
    script = load_script(script_path, interface)
    names, external = resolve(args.sut, world_file.parent, args.time_scale)
    if len(names) != 1:
        raise UntimelyError(f"--sut {args.sut!r}: run takes one SUT; a campaign takes several")
    sut = names[0]
    _world_given(args.world, world_file, sut not in external)
    # Opened before the run: a store another process writes is refused before a long real-time
    # run, and an external SUT is told the trace id it is making (its hello's `run`).
    con = store.connect(args.db)
    setup = transport.setup(run_script, interface_path, world_file, args.max_delay, external)
    trace = setup.transport(sut).run(script, args.seed, interface, 0, store.next_id(con, "traces", "trace_id"))
    # the target folder: analyze, explain and shrink read its properties and files
    record = RunRecord(sut=sut, max_delay=args.max_delay, target=str(interface_path.resolve().parent),
                       **({"external": {sut: external[sut]}} if sut in external else {}))
    with store.transaction(con):
        campaign_id = store.next_id(con, "campaigns", "campaign_id")
        store.add_campaign(con, campaign_id, str(script_path), args.seed, record)
        store.add_reply_codes(con, interface)
        script_id = store.next_id(con, "scripts", "script_id")
        store.add_scripts(con, [store.ScriptRow(script_id, campaign_id, "golden", script.render())])
        trace_id = store.next_id(con, "traces", "trace_id")
        store.insert_trace(con, trace_id, campaign_id, script_id, trace)
    print(f"trace {trace_id} of {script_path} on {sut} (seed {args.seed}) stored in {args.db}")
    print(summary(trace, interface.replies))
    return 0 if trace.outcome == "completed" else 1
