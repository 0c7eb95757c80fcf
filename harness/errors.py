"""One base exception for the bench; every message quotes the bad value and says what to do."""


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
