"""A tiny driver for the simulated layer's tests: send requests at chosen times, record replies.

No executive, no observation delay: requests reach the layer exactly when sent.
"""
from __future__ import annotations

from harness import DEFAULT_MISSION_DIR
from harness.sut.simulated.kernel import Environment
from harness.sut.simulated.layer import FunctionalLayer

WORLD = DEFAULT_MISSION_DIR / "world.toml"
SETTINGS = {  # what the golden mission configures
    "rflex.SetMode": {"mode": "velocity"},
    "sick.SetParams": {"fov": "180", "range": "8"},
    "ndd.SetParams": {"speed": "0.6"},
    "antenna.SetChannel": {"channel": "3"},
}


class Driver:
    def __init__(self, variant: str, interface, world=WORLD):
        self.env = Environment()
        self.layer = FunctionalLayer(self.env, variant, interface, world)
        self.services: dict[int, str] = {}
        self.replies: list[tuple[float, int, str, str | None]] = []  # (t, rqst_id, kind, code)
        rflex = self.layer.modules["rflex"]  # Dala's modules share the world and the posters
        self.world, self.posters = rflex.world, rflex.posters

    def send(self, at: float, service: str, **args) -> int:
        rqst_id = len(self.services) + 1
        self.services[rqst_id] = service
        raw = {k: str(v) for k, v in args.items()}
        self.env.call_at(at, lambda: self.layer.receive(rqst_id, service, raw, self._record))
        return rqst_id

    def _record(self, rqst_id: int, kind: str, code: str | None) -> None:
        self.replies.append((self.env.now, rqst_id, kind, code))

    def prepare(self, *modules: str, configure: bool = True) -> float:
        """Init the modules (all by default) at 0 and configure them as the golden mission does;
        returns the time from which they are ready."""
        modules = modules or tuple(self.layer.modules)
        for module in modules:
            self.send(0.0, f"{module}.Init")
        if configure:
            for service, args in SETTINGS.items():
                if service.split(".")[0] in modules:
                    self.send(0.6, service, **args)
        return 1.0

    def run(self, until: float) -> "Driver":
        self.env.run(until=until)
        return self

    def final(self, rqst_id: int) -> str | None:
        return next((code for _, r, kind, code in self.replies if r == rqst_id and kind == "final"), None)

    def when(self, rqst_id: int, kind: str = "final") -> float | None:
        return next((t for t, r, k, _ in self.replies if r == rqst_id and k == kind), None)

    def ping(self, at: float) -> list[float]:
        """Probe liveness at `at`; the returned list gets the answer time, if any."""
        answers: list[float] = []
        self.env.call_at(at, lambda: self.layer.ping(lambda: answers.append(self.env.now)))
        return answers

    def world_kinds(self) -> list[str]:
        return [kind for _, kind, _ in self.layer.world_events]
