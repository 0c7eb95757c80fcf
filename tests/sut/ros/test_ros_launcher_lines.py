"""The ROS launchers' stdio (harness/sut/roscommon/lines.py): what a library in the launcher writes to
stdout by itself (Fast DDS logs errors to std::cout) goes to stderr, never between protocol lines."""
import json
import subprocess
import sys
import textwrap

from tests.support.paths import ROOT

LAUNCHER = textwrap.dedent("""
    import os, sys
    from harness.sut.roscommon.lines import run_main

    def run(args, out):
        os.write(1, b"[RTPS_TRANSPORT_SHM Error] Failed init_port\\n")  # as a C++ library writes
        print("a print of the launcher's own")
        out.write({"op": "error", "message": "the one protocol line"})

    sys.exit(run_main(run, None))
""")


def test_what_a_library_writes_to_stdout_goes_to_stderr_and_the_protocol_keeps_whole_lines():
    done = subprocess.run([sys.executable, "-c", LAUNCHER], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert [json.loads(line) for line in done.stdout.splitlines()] == [
        {"op": "error", "message": "the one protocol line"}], done.stdout
    assert "Failed init_port" in done.stderr and "a print of the launcher's own" in done.stderr
