import pytest

from tests.integration.harness import running_system


@pytest.fixture(scope="module")
def system():
    """The default system, shared by the tests of one module that do not disturb it."""
    with running_system() as s:
        yield s
