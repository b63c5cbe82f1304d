"""Shared fixtures: the repository root (the tests and doctests use paths relative to it) and
the bundled robots."""

import os
import pathlib

import numpy as np
import pytest

import kinetree

ROOT = pathlib.Path(__file__).resolve().parents[3]
REFERENCE = ROOT / "tests" / "data" / "reference"
PANDA = ROOT / "tests" / "data" / "robots" / "panda.urdf"


@pytest.fixture(autouse=True, scope="session")
def _at_repo_root():
    """Docstrings load "tests/data/robots/panda.urdf": run everything from the repository root."""
    old = os.getcwd()
    os.chdir(ROOT)
    yield
    os.chdir(old)


@pytest.fixture(scope="session")
def panda():
    return kinetree.Model.from_urdf(str(PANDA))


@pytest.fixture(scope="session")
def talos():
    return kinetree.Model.from_urdf(str(REFERENCE / "urdf" / "talos_reduced.urdf"), floating=True)


@pytest.fixture
def rng():
    return np.random.default_rng(7)
