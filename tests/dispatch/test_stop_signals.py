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


# Ctrl-C while a shrink is stored: DuckDB turns the KeyboardInterrupt raised during its query into
# RuntimeError('Query interrupted'), which the broad except of one behaviour's failure caught, and the
# repeat was ignored: the campaign ran on and exited 0 (issue 48).
LOST_IN_A_QUERY = textwrap.dedent("""
    import os, signal, threading, types
    import duckdb
    from harness.campaign import representatives
    from harness.sut import processes

    def stored(con, *_):
        threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
        con.execute("select count(*) from range(2000000000) t(a) where a % 7 = 3").fetchall()
        return "stored"

    representatives.stored = stored
    processes.stop_on_signals()
    try:
        task = types.SimpleNamespace(behaviour="FN on P on v", crashed=lambda error: "crashed: " + error)
        print(representatives._stored(duckdb.connect(), task, None, None), flush=True)
    except KeyboardInterrupt:
        print("stopped", flush=True)
""")


def test_a_stop_that_duckdb_made_an_error_inside_a_broad_except_still_stops_the_bench():
    done = subprocess.run([sys.executable, "-c", LOST_IN_A_QUERY], cwd=ROOT, capture_output=True, text=True,
                          timeout=180)
    assert done.stdout.splitlines() == ["stopped"], done
