"""What the Dala module descriptions say the layer must enforce (DESIGN §3), as the layer knows it.

This is the implementation's own, hard-coded knowledge: it never reads properties.toml, which
is the tester's view. Which of these rules a variant actually enforces is in variants.py.
"""

# AIB: a running activity x is interrupted by these requests of its own module.
# Every module's Stop also dominates each of its activities (see `dominates`).
DOMINATORS = {
    "rflex.TrackSpeedStart": {"rflex.TrackSpeedStart"},
    "sick.ContinuousShot": {"sick.ContinuousShot", "sick.OneShot"},
    "sick.OneShot": {"sick.ContinuousShot"},
    "aspect.Fuse": {"aspect.Fuse", "aspect.Reset"},
    "ndd.GotoPosition": {"ndd.GotoPosition"},
    "antenna.Point": {"antenna.Point"},
    "antenna.Communication": {"antenna.Communication", "antenna.Point"},
}

# PRE: an exec request x needs every service of its set to have ended ok before.
REQUIREMENTS = {
    "rflex.TrackSpeedStart": {"rflex.SetMode"},
    "sick.ContinuousShot": {"sick.SetParams"},
    "sick.OneShot": {"sick.SetParams"},
    "aspect.Fuse": {"aspect.Reset"},
    "ndd.GotoPosition": {"ndd.SetParams"},
    "antenna.Communication": {"antenna.Point", "antenna.SetChannel"},
}

# EXC: these pairs never run together; the latest request wins.
EXCLUSIONS = (
    ("antenna.Communication", "ndd.GotoPosition"),
    ("antenna.Point", "ndd.GotoPosition"),
    ("aspect.Reset", "ndd.GotoPosition"),
)


def is_stop(service: str) -> bool:
    return service.endswith(".Stop")


def dominates(request: str, activity: str) -> bool:
    """Whether a request interrupts a running activity of the same module (AIB)."""
    if is_stop(request):
        return not is_stop(activity)
    return request in DOMINATORS.get(activity, ())


def excluded_by(request: str) -> set[str]:
    """The activities (of any module) that may not run once `request` has started (EXC)."""
    return {b if a == request else a for a, b in EXCLUSIONS if request in (a, b)}
