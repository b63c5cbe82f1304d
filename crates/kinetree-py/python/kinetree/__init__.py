"""kinetree: kinematics, dynamics, inverse kinematics, reachable workspace and collision of
articulated rigid bodies, computed in Rust, from numpy.

Load a model and compute with numpy arrays in SI units; every per-state call also takes a stack
of states (``q`` of shape ``(N, nq)``) and computes them in parallel with the GIL released:

>>> import kinetree, numpy as np
>>> panda = kinetree.Model.from_urdf("tests/data/robots/panda.urdf")
>>> q = panda.random_configuration(1000, seed=0)
>>> panda.link_placements(q).shape
(1000, 13, 4, 4)
>>> panda.crba(q).shape
(1000, 9, 9)

Errors are ``kinetree.KinetreeError`` (a ``ValueError``) subclasses, one per family:
``ModelError``, ``KinematicsError``, ``DynamicsError``, ``CollisionError``, ``IkError``.
"""

from ._kinetree import *  # noqa: F401,F403
from ._kinetree import __version__  # noqa: F401
from . import _kinetree

__all__ = [name for name in dir(_kinetree) if not name.startswith("_")]

# The classes are defined in the extension; present them as members of this package.
for _name in __all__:
    _obj = getattr(_kinetree, _name)
    if isinstance(_obj, type):
        try:
            _obj.__module__ = "kinetree"
        except (AttributeError, TypeError):
            pass
del _name, _obj
