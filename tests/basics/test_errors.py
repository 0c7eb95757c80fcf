"""Every error class of the bench survives pickling (a worker process hands its errors over so)."""
import importlib
import inspect
import pickle
import pkgutil
import signal

import harness
from harness.errors import BudgetSpent, InputFileError, InternalSignal, ScriptError, UntimelyError
from harness.sut.processes import Stopped


def _modules():
    for info in pkgutil.walk_packages(harness.__path__, "harness."):
        if info.name == "harness.__main__":  # runs the command line
            continue
        try:
            yield importlib.import_module(info.name)
        except ImportError:  # an optional extra (ROS) that is not installed
            continue


def _error_classes() -> set[type]:
    return {cls for module in _modules() for _, cls in inspect.getmembers(module, inspect.isclass)
            if issubclass(cls, BaseException) and cls.__module__.startswith("harness.")}


def _instance(cls: type) -> BaseException:
    if cls is Stopped:  # made from the number of the signal that stopped the bench
        return cls(signal.SIGTERM)
    if issubclass(cls, InputFileError):
        return cls("missions/x/golden.mission", "line 3", "unknown service 'rflex.Fly'; use one of Init, Stop")
    return cls("the bench's message, quoting 'the value'")


def test_every_error_class_pickles_with_its_message_and_fields():
    classes = _error_classes()
    assert {UntimelyError, InputFileError, ScriptError} <= classes and len(classes) >= 8
    for cls in classes:
        error = _instance(cls)
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is cls and str(again) == str(error) and vars(again) == vars(error), cls
    script = pickle.loads(pickle.dumps(_instance(ScriptError)))
    assert (script.path, script.where, script.problem) == (
        "missions/x/golden.mission", "line 3", "unknown service 'rflex.Fly'; use one of Init, Stop")


def test_every_user_error_lives_in_errors_py_and_every_other_exception_is_an_internal_signal():
    """errors.py is the one home of what a user may read; an exception class defined elsewhere is
    one of the bench's internal signals, and says so by its base (or is how a signal stops the bench)."""
    outside = {f"{cls.__module__}.{cls.__qualname__}": cls for cls in _error_classes() if cls.__module__ != "harness.errors"}
    users = {name for name, cls in outside.items() if issubclass(cls, UntimelyError)}
    assert users == set(), "define user errors in harness/errors.py"
    unmarked = {name for name, cls in outside.items()
                if not issubclass(cls, (UntimelyError, InternalSignal)) and cls is not Stopped}
    assert not unmarked, "an internal signal derives from harness.errors.InternalSignal"
    assert {InternalSignal, BudgetSpent} <= _error_classes()
