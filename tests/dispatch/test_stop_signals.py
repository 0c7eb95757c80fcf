"""A stop signal stops the bench even when it lands in a finalizer, where Python swallows what a
signal handler raises (a campaign once ran on after a SIGTERM raised in a pipe's `__del__`)."""
import subprocess
import sys
import textwrap

from harness import ROOT

SWALLOWED_ONCE = textwrap.dedent("""
    import gc, os, signal, time
    from harness.sut import processes

    class Finalized:
        def __del__(self):  # the signal arrives while this runs: its handler raises here
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(100_000):
                pass

    processes.stop_on_signals()
    try:
        Finalized()
        gc.collect()
        print("went on", flush=True)
        time.sleep(5)
        print("not stopped", flush=True)
    except processes.Stopped as stop:
        print("stopped by", stop, flush=True)
""")


def test_a_stop_swallowed_by_a_finalizer_is_raised_again_in_the_bench_s_own_code():
    done = subprocess.run([sys.executable, "-c", SWALLOWED_ONCE], cwd=ROOT, capture_output=True, text=True,
                          timeout=30)
    assert done.stdout.splitlines() == ["went on", "stopped by SIGTERM"], done
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr
