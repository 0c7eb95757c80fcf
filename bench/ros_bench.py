"""ROS 1 SUT figures: launcher start-up (master + node + adapter ready), and the wall-clock round trip
of a control request (rflex.SetMode) through ROS, beside the same through the out-of-process simulator
adapter, alone and with eight SUTs at once. Skips, saying why, where ROS is not installed."""
import queue
import statistics
import subprocess
import sys
import threading
import time

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.sut.external.channel import Connection
from harness.target.interface import load_interface
from harness.sut.protocol import PROTO, decode, encode
from harness.sut.definitions import load_suts_file
from harness.target.suts import ExternalSut

ROUND_TRIPS = 150
INTERFACE = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
SIM = ExternalSut("sim-reference", command="{python} -m harness.sut.simulated --variant reference")


class Client:
    """One SUT on stdio: start-up time, then control requests one at a time."""

    def __init__(self, sut: ExternalSut, slot: int):
        self.lines: queue.Queue = queue.Queue()
        started = time.monotonic()
        self.connection = Connection(sut, slot)
        self.connection.start(self.deliver)
        self.connection.write(encode("hello", proto=PROTO, run=slot, seed=0, time_scale=1.0,
                                     interface=INTERFACE.describe()))
        self.next(lambda m: m["op"] == "hello")
        self.startup_s = time.monotonic() - started
        self.ids = iter(range(1, 10**6))

    def deliver(self, lines: list[str] | None) -> None:
        """The reader thread's lines, one by one; None when the SUT's output ends."""
        for line in lines or [None]:
            self.lines.put(line)

    def next(self, wanted) -> dict:
        while True:
            line = self.lines.get(timeout=120)
            if line is None:
                raise RuntimeError("the SUT ended: " + self.connection.stderr_tail())
            message = decode(line)
            if wanted(message):
                return message

    def final(self, service: str, **args) -> tuple[str, float]:
        rqst_id, (module, name) = next(self.ids), service.split(".")
        sent = time.monotonic()
        self.connection.write(encode("request", id=rqst_id, module=module, service=name, args=args))
        reply = self.next(lambda m: m["op"] == "reply" and m["id"] == rqst_id and m["kind"] == "final")
        return reply["code"], time.monotonic() - sent

    def round_trips(self, count: int) -> list[float]:
        assert self.final("rflex.Init")[0] == "ok"
        trips = []
        for n in range(count):
            code, seconds = self.final("rflex.SetMode", mode=("velocity", "idle")[n % 2])
            assert code == "ok", code
            trips.append(seconds)
        return trips

    def close(self) -> None:
        self.connection.write(encode("bye"))
        self.connection.close()


def measure(sut: ExternalSut, slots: int) -> tuple[list[float], list[float]]:
    """Start-up times and round trips of `slots` SUTs started and driven at once."""
    clients: list[Client] = []
    trips: list[float] = []
    lock = threading.Lock()

    def one(slot: int) -> None:
        client = Client(sut, slot)
        with lock:
            clients.append(client)
        mine = client.round_trips(ROUND_TRIPS)
        with lock:
            trips.extend(mine)
    threads = [threading.Thread(target=one, args=(slot,)) for slot in range(slots)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for client in clients:
        client.close()
    if len(clients) != slots:
        raise RuntimeError(f"only {len(clients)} of {slots} SUTs started")
    return [c.startup_s for c in clients], trips


def ms(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return 1000 * ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def main() -> int:
    probe = subprocess.run(["/usr/bin/python3", "-c", "import rospy, actionlib"], capture_output=True)
    if probe.returncode or not (ROOT / ".venv-ros" / "bin" / "python").exists():
        print("skipped: /usr/bin/python3 cannot import rospy, or .venv-ros is missing (make ros)")
        return 0
    ros = load_suts_file(DEFAULT_MISSION_DIR / "suts.toml")["ros-reference"]
    figures = {}
    for slots in (1, 8):
        for name, sut in (("sim", SIM), ("ros", ros)):
            startups, trips = measure(sut, slots)
            figures[name, slots] = trips
            print(f"{name} x{slots}: start-up median {statistics.median(startups):.2f} s, max {max(startups):.2f} s; "
                  f"SetMode round trip p50 {ms(trips, 0.5):.2f} ms, p95 {ms(trips, 0.95):.2f} ms "
                  f"({len(trips)} requests)", flush=True)
        print(f"ROS over the simulator adapter, {slots} at once: p50 x{ms(figures['ros', slots], 0.5) / ms(figures['sim', slots], 0.5):.1f}, "
              f"p95 x{ms(figures['ros', slots], 0.95) / ms(figures['sim', slots], 0.95):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
