"""Shared fixtures of the suite.

Every test starts with the registry of deprecation warnings already issued emptied: an
old spelling warns once per process, so without it whether a test sees the warning would
depend on which tests ran before it.
"""

import pytest

from tendonrod import _deprecation


@pytest.fixture(autouse=True)
def _fresh_deprecations():
    _deprecation._warned.clear()
    yield
    _deprecation._warned.clear()
