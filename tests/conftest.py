import pytest

from harness import DEFAULT_MISSION_DIR
from harness.interface import load_interface, load_properties


@pytest.fixture(scope="session")
def interface():
    return load_interface(DEFAULT_MISSION_DIR / "interface.toml")


@pytest.fixture(scope="session")
def properties(interface):
    return load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
