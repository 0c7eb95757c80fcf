"""No process left behind: what the bench starts, it ends, however it is itself ended.

An adapter runs in a process group of its own; ending it is SIGTERM to the group, a grace, then
SIGKILL to the group (an adapter that ignores SIGTERM, its children with it). A daemon that
double-forks and calls setsid leaves that group: on Linux the bench is a child subreaper
(prctl PR_SET_CHILD_SUBREAPER), so such orphans become its children, and `end_orphans` ends
them. SIGTERM and SIGHUP become `Stopped` (a KeyboardInterrupt), so the same cleanup as for
Ctrl-C runs. What cannot be caught: SIGKILL of the bench itself (its workers and adapters are
then told by PR_SET_PDEATHSIG where they asked for it), and a daemon that escapes to another
subreaper or into another cgroup (systemd-run, a container runtime).

The adapters' own children (a rosmaster, the SUT's node, a recorder) are `Child`ren: their stderr
forwarded, told by PR_SET_PDEATHSIG when the adapter dies, ended as the bench ends its adapters.
"""
from __future__ import annotations

import collections
import ctypes
import os
import signal
import subprocess
import sys
import threading
import time

from harness.errors import ChildError

PR_SET_PDEATHSIG = 1
PR_SET_CHILD_SUBREAPER = 36
TERM_GRACE_S = 2.0  # between SIGTERM and SIGKILL


class Stopped(KeyboardInterrupt):
    """The bench was told to stop by a signal other than SIGINT."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    def __reduce__(self):
        return type(self), (self.signum,)


STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


_STOPPING: list[int] = []  # the signal of the stop under way, once it came


def _stop(signum: int) -> KeyboardInterrupt:
    return KeyboardInterrupt() if signum == signal.SIGINT else Stopped(signum)


def _raise_stopped(signum, _frame):
    for repeated in _handled():  # a repeat must not cut the cleanup short (a worker gets its
        signal.signal(repeated, _stopping)  # parent-death signal once per parent thread; a second Ctrl-C is a habit)
    _STOPPING.append(signum)
    raise _stop(signum)


def raise_if_stopping() -> None:
    """Raise the stop under way, if one came: for a broad `except` that may have caught what the
    stop became (DuckDB turns a KeyboardInterrupt raised during a query into RuntimeError('Query
    interrupted')); the repeats of the signal are ignored from its first, so a stop lost there
    would let the bench run on and exit 0."""
    stop = stop_under_way()
    if stop:
        raise stop


def stop_under_way() -> KeyboardInterrupt | None:
    """The stop signal that came, as the exception it raised, or None: DuckDB turns one raised while
    it reads Python objects into another error (a table not found, a schema not read)."""
    return _stop(_STOPPING[0]) if _STOPPING else None


def _handled() -> tuple:
    """The signals that stop the bench: Ctrl-C too, unless ignored (a worker's parent stops it)."""
    return STOP_SIGNALS + (() if signal.getsignal(signal.SIGINT) is signal.SIG_IGN else (signal.SIGINT,))


def _stopping(_signum, _frame):
    """Already stopping: nothing more to do (a handler, not SIG_IGN, which adapters would inherit)."""


def stop_on_signals() -> None:
    """SIGTERM and SIGHUP stop the bench as Ctrl-C does: cleanup runs, the store keeps what is committed;
    a stop signal or Ctrl-C during that cleanup is ignored."""
    for signum in _handled():
        signal.signal(signum, _raise_stopped)
    if sys.unraisablehook is not _stop_again:
        _stop_again.previous = sys.unraisablehook
        sys.unraisablehook = _stop_again


REDELIVER_S = 0.05  # after the finalizer that swallowed a stop has returned


def _stop_again(unraisable) -> None:
    """A stop raised inside a finalizer (a `__del__` the garbage collector ran) cannot propagate:
    Python reports it here and carries on. It is delivered again, from a timer thread, so that it
    is raised in the main thread's own code (a signal sent from here would be raised in this hook)."""
    stop = unraisable.exc_value
    signum = getattr(stop, "signum", signal.SIGINT)
    if not isinstance(stop, KeyboardInterrupt) or sys.is_finalizing() or signum not in _handled():
        _stop_again.previous(unraisable)
        return
    signal.signal(signum, _raise_stopped)
    again = threading.Timer(REDELIVER_S, os.kill, (os.getpid(), signum))
    again.daemon = True
    again.start()


try:  # looked up before any fork: a child's preexec_fn only calls it
    _PRCTL = getattr(ctypes.CDLL(None, use_errno=True), "prctl", None)  # Linux only
except OSError:
    _PRCTL = None


def _prctl(option: int, value: int) -> bool:
    return _PRCTL is not None and _PRCTL(option, value, 0, 0, 0) == 0


def become_subreaper() -> bool:
    """Orphans of the processes this one starts become its children (Linux); False elsewhere."""
    return _prctl(PR_SET_CHILD_SUBREAPER, 1)


def die_with_parent(signum: int = signal.SIGTERM) -> bool:
    """This process gets `signum` when its parent dies (Linux); False elsewhere."""
    return _prctl(PR_SET_PDEATHSIG, signum)


def dying_with_parent(signum: int):
    """A preexec_fn: the child gets `signum` when the process that starts it dies (Linux)."""
    return lambda: die_with_parent(signum)


def end(processes: list[subprocess.Popen], grace_s: float = TERM_GRACE_S, groups: bool = False) -> None:
    """SIGTERM to each process (with `groups`, to the process group it leads) all at once, so that
    their shutdowns overlap; SIGKILL to whatever outlives `grace_s` (with `groups`, to whatever is
    left of each group, children included, once its leader exited or the grace passed); each reaped."""
    for process in processes:
        if groups:
            _signal_group(process.pid, signal.SIGTERM)
        elif process.poll() is None:
            process.terminate()
    deadline = time.monotonic() + grace_s
    for process in processes:
        try:
            process.wait(max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            pass
        if groups:
            _signal_group(process.pid, signal.SIGKILL)
        elif process.poll() is None:
            process.kill()
        process.wait()


def _signal_group(pgid: int, signum: int) -> bool:
    try:
        os.killpg(pgid, signum)
        return True
    except (ProcessLookupError, PermissionError):
        return False


def uptime() -> float:
    """Seconds since boot, the clock of /proc/PID/stat's start times (0 where there is none)."""
    try:
        with open("/proc/uptime") as f:
            return float(f.read().split()[0])
    except OSError:
        return 0.0


def _detached_children(since: float) -> list[int]:
    """This process's children in another session than its own, started `since` seconds after
    boot or later, from /proc: adapters and what they detached, never a helper of this process
    (a worker, the multiprocessing resource tracker), which shares its session."""
    found, me, session, tick = [], os.getpid(), os.getsid(0), os.sysconf("SC_CLK_TCK")
    try:
        entries = [e for e in os.listdir("/proc") if e.isdigit()]
    except OSError:
        return found
    for entry in entries:
        try:
            with open(f"/proc/{entry}/stat", "rb") as f:
                stat = f.read().decode(errors="replace")
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2:].split()  # from the state on: the name may hold spaces
        if int(fields[1]) == me and int(fields[3]) != session and int(fields[19]) / tick >= since - 1 / tick:
            found.append(int(entry))
    return found


def end_orphans(since: float, known: set[int] = frozenset(), grace_s: float = TERM_GRACE_S) -> int:
    """End and reap the children of this process started since `since` (uptime()) in another
    session, but those `known`: adapters and daemons re-parented to it as a subreaper. Returns
    how many. They get `grace_s` to exit by themselves (a recorder told by its death signal closes
    its bag), then SIGKILL: they were detached from the adapter's group on purpose."""
    orphans = [pid for pid in _detached_children(since) if pid not in known]
    deadline = time.monotonic() + grace_s
    left = set(orphans)
    while left and time.monotonic() < deadline:
        left = {pid for pid in left if not _reaped(pid)}
        if left:
            time.sleep(0.02)
    for pid in left:
        try:
            if os.getpgid(pid) == pid:
                _signal_group(pid, signal.SIGKILL)
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        try:
            os.waitpid(pid, 0)
        except ChildProcessError:
            pass
    return len(orphans)


def _reaped(pid: int) -> bool:
    """Whether the child `pid` has exited (and is now reaped)."""
    try:
        return os.waitpid(pid, os.WNOHANG)[0] == pid
    except ChildProcessError:
        return True


class Child:
    """A process whose stderr is forwarded to ours, keeping its last lines for error messages."""

    def __init__(self, name: str, argv: list[str], env: dict[str, str], death_signal: int = signal.SIGKILL,
                 own_group: bool = False):
        """`death_signal` reaches the child when the launcher dies; `own_group` keeps it out of the
        launcher's process group, which the bench kills after its grace period."""
        self.name, self.argv = name, argv
        try:
            self.process = subprocess.Popen(argv, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                            stderr=subprocess.PIPE, text=True, errors="replace",
                                            preexec_fn=dying_with_parent(death_signal), start_new_session=own_group)
        except OSError as e:
            raise ChildError(f"cannot start the {name} ({' '.join(argv)!r}): {e}; check the command") from None
        self.last_lines: collections.deque[str] = collections.deque(maxlen=20)
        threading.Thread(target=self._forward, name=f"{name} stderr", daemon=True).start()

    def _forward(self) -> None:
        for line in self.process.stderr:
            self.last_lines.append(line.rstrip("\n"))
            print(f"[{self.name}] {line}", end="", file=sys.stderr, flush=True)

    def failure(self) -> str | None:
        """Why the child is no longer running, with its last stderr lines; None while it runs."""
        status = self.process.poll()
        if status is None:
            return None
        return f"the {self.name} exited with status {status}; its last lines: " + " | ".join(self.last_lines)

    def stop(self, grace_s: float = 5.0) -> None:
        stop_all([self], grace_s)


def stop_all(children: list[Child], grace_s: float = 5.0) -> None:
    end([child.process for child in children], grace_s)
