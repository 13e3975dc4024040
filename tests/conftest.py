import numpy as np
import pytest

from fivebar_drake.robots.quadruped.config import load_params


@pytest.fixture(scope="session")
def params():
    return load_params()


@pytest.fixture()
def rng():
    return np.random.default_rng(20261121)
