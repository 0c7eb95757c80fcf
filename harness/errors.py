"""Every error the bench reports to a user, on one base (UntimelyError): each message quotes the bad
value and says what to do. Beside them, the one base of the bench's internal signals
(InternalSignal): raised and caught inside the bench, never shown to a user as they are."""


class UntimelyError(Exception):
    """Base of every error the bench reports to a user (the CLI prints it without a traceback)."""


class InputFileError(UntimelyError):
    """A malformed input file: names the file, the line or entry, and the bad value."""

    def __init__(self, path, where, problem):
        self.path, self.where, self.problem = str(path), where, problem
        super().__init__(f"{self.path}:{where}: {problem}" if where != "" else f"{self.path}: {problem}")

    def __reduce__(self):
        """Rebuilt from its three parts (a worker process hands its errors over pickled)."""
        return type(self), (self.path, self.where, self.problem)


class ScriptError(InputFileError):
    """A mission script that cannot be run (unknown module, service, handle or argument)."""


class PropertyError(UntimelyError):
    """A property that cannot be rendered into an oracle query."""


class StoreError(UntimelyError):
    """The trace store refuses an operation (wrong campaign, corrupt or missing data)."""


class BudgetSpent(UntimelyError):
    """A focused campaign's shrink run that would not fit in its budget (the shrink's failure)."""

    def __init__(self, message: str = "the budget is spent"):
        super().__init__(message)


class ChildError(UntimelyError):
    """A child process (a rosmaster, a rosbag recorder, a SUT's node) could not start or died during
    start-up (the launcher reports it as `error`)."""


class Ros2Error(UntimelyError):
    """ROS 2 is missing for a distro, or no domain id is free."""


class InternalSignal(Exception):
    """Base of what the bench raises to tell another part of itself how something ended (a SUT
    that stopped reading, a protocol line that is not one, a kernel process interrupted); each is
    caught and turned into an outcome or an UntimelyError before a user sees it."""
