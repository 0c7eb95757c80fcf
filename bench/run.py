"""`make bench`: run every benchmark script in this folder (bench/*_bench.py), one after another.

Each prints its own figures (ratios, events/second) with the machine it ran on; its output is also
kept in reports/bench/<name>.txt, from which bench/readme_table.py rewrites the README's rows that
a bench measures (its lines `README: what | measured | target`). A bench that crashes (a non-zero
exit) fails `make bench`; a slow one does not, since a busy machine is slow. Pass names to run
only some: `python bench/run.py golden analyzer`.
"""
import os
import platform
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
KEPT = HERE.parent / "reports" / "bench"


def run(script: Path) -> int:
    """Run one bench, its output printed as it comes and kept in KEPT; its exit status."""
    KEPT.mkdir(parents=True, exist_ok=True)
    with open(KEPT / f"{script.stem.removesuffix('_bench')}.txt", "w") as kept:
        child = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True, bufsize=1)
        for line in child.stdout:
            print(line, end="", flush=True)
            kept.write(line)
        return child.wait()


def main(names: list[str]) -> int:
    scripts = sorted(HERE.glob("*_bench.py"))
    known = [s.stem.removesuffix("_bench") for s in scripts]
    unknown = [n for n in names if n not in known]
    if unknown:
        print(f"no bench named {unknown[0]!r}; name some of: {', '.join(known)}", file=sys.stderr)
        return 2
    if names:
        scripts = [script for script, name in zip(scripts, known) if name in names]
    print(f"machine: {platform.processor() or platform.machine()}, {platform.system()} "
          f"{platform.release()}, python {platform.python_version()}, "
          f"{os.cpu_count()} cores", flush=True)
    failed = []
    for script in scripts:
        print(f"\n== {script.stem} ==", flush=True)
        if run(script) != 0:
            failed.append(script.stem)
    if failed:
        print(f"\nfailed (crashed): {', '.join(failed)}")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
