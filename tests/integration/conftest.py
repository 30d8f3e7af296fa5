import pytest

from tests.integration.harness import running_system
from tests.integration.launches import CUSTOM


@pytest.fixture(scope="module")
def system():
    """The default system, shared by the tests of one module that do not disturb it."""
    with running_system() as s:
        yield s


@pytest.fixture(scope="module")
def custom(tmp_path_factory):
    """A system from tests.integration.launches.CUSTOM: three obstacles, every node's
    parameters set, a respawning status monitor."""
    path = tmp_path_factory.mktemp("launch") / "custom.toml"
    path.write_text(CUSTOM)
    with running_system(path) as system:
        yield system
