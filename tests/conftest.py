"""Shared fixtures of the suite: ``rod``, the 0.2 m / 0.8 mm wire most scenes start from;
and, for every test, the registry of deprecation warnings already issued emptied (an old
spelling warns once per process: without it whether a test sees the warning would depend
on which tests ran before it)."""

import pytest

import tendonrod as tr
from tendonrod import _deprecation


@pytest.fixture(autouse=True)
def _fresh_deprecations():
    _deprecation._warned.clear()
    yield
    _deprecation._warned.clear()


@pytest.fixture
def rod():
    """The suite's workhorse backbone: a 0.2 m spring-steel wire of 0.8 mm diameter
    (E = 207 GPa, G = 79.6 GPa), unshearable and inextensible (the paper's Section IV-B
    rod; EI = 4.17e-3 N m^2, EI/L^2 = 0.104 N).  A frozen dataclass: safe to share."""
    return tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
