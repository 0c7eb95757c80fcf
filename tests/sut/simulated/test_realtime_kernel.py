"""The kernel in wall-clock time: pacing, posts from other threads, and a late kernel that still
takes messages in (a busy machine must not starve a SUT's pings into a false hang)."""
import threading
import time

from harness.sut.simulated.realtime import RealtimeEnvironment


def test_events_wait_for_the_clock_and_posts_run_at_its_reading():
    env = RealtimeEnvironment(time_scale=10)
    seen = []

    def process():
        yield env.timeout(10.0)  # 1 s of wall time: the post below comes first however busy the machine
        seen.append(("timeout", env.now, env.clock()))
    done = env.process(process())
    threading.Timer(0.05, lambda: env.post(lambda: seen.append(("posted", env.now, env.clock())))).start()
    env.run(until=done)
    (posted, at, clock), (timeout, t, t_clock) = seen
    assert (posted, timeout) == ("posted", "timeout")
    assert 0.4 < at <= clock < 10.0  # 50 ms wall at 10x, not before
    assert t == 10.0 and 10.0 <= t_clock < 30.0


def test_a_late_kernel_still_takes_posted_messages_at_its_own_time():
    env = RealtimeEnvironment(time_scale=10)

    def costly_codel():  # 2 ms of work every 1 ms of wall time: the kernel falls ever further behind
        while True:
            yield env.timeout(0.01)
            start = time.perf_counter()
            while time.perf_counter() - start < 0.002:
                pass
    env.process(costly_codel())
    stop, taken = env.event(), []
    kernel = threading.Thread(target=lambda: env.run(until=stop))
    kernel.start()
    time.sleep(0.3)
    sent = time.monotonic()
    env.post(lambda: taken.append((time.monotonic() - sent, env.now, env.clock())))
    time.sleep(2.0)
    env.post(lambda: stop.succeed())
    kernel.join(5.0)
    assert not kernel.is_alive() and len(taken) == 1
    waited, at, clock = taken[0]
    assert waited < 1.5 and at < clock  # taken at once (before the stop was posted), at the kernel's (late) time
