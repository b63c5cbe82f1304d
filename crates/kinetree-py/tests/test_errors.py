"""The bad-input catalogue: every input error is a kinetree exception of its family (a
ValueError) with a message naming what is wrong; none crashes the interpreter or escapes as a
Rust panic (pyo3's PanicException is a BaseException, not an Exception)."""

import numpy as np
import pytest

import kinetree

NAN = float("nan")


def catalogue(panda):
    q, v = panda.neutral(), np.zeros(9)
    E = kinetree
    return [
        # (exception, fragment of the message, call)
        (E.ModelError, "no/such.urdf", lambda: kinetree.Model.from_urdf("no/such.urdf")),
        (E.ModelError, "", lambda: kinetree.Model.from_urdf("<robot name='x'><link/></robot>")),
        (E.ModelError, "", lambda: kinetree.Model.from_urdf("<robot")),
        (E.ModelError, "", lambda: kinetree.Model.from_json("{\"name\": 3}")),
        (E.ModelError, "path", lambda: kinetree.Model.from_urdf(42)),
        (E.ModelError, "(4,) or (N, 4)", lambda: kinetree.Model.from_dh([[1.0, 0.0]])),
        (E.ModelError, "kinds", lambda: kinetree.Model.from_dh([[1.0, 0, 0, 0]], kinds=["screw"])),
        (E.ModelError, "kinds", lambda: kinetree.Model.from_dh([[1.0, 0, 0, 0]], kinds=[])),
        (E.ModelError, "", lambda: kinetree.Model.from_dh([[NAN, 0, 0, 0]])),
        (E.KinematicsError, "(9,) or (N, 9)", lambda: panda.link_placements(np.zeros(8))),
        (E.KinematicsError, "got (2, 3, 9)", lambda: panda.link_placements(np.zeros((2, 3, 9)))),
        (E.KinematicsError, "float64", lambda: panda.link_placements("abc")),
        (E.KinematicsError, "float64", lambda: panda.link_placements(np.full(9, 1 + 2j))),
        (E.KinematicsError, "q[0] is NaN", lambda: panda.link_placements([None] * 9)),  # numpy reads None as NaN
        (E.KinematicsError, "q[3] is NaN", lambda: panda.link_placements(np.where(np.arange(9) == 3, NAN, 0.0))),
        (E.KinematicsError, "q[1, 2] is inf", lambda: panda.link_placements(np.where(np.arange(18).reshape(2, 9) == 11, np.inf, 0.0))),
        (E.KinematicsError, "no_such_link", lambda: panda.frame_jacobian(q, "no_such_link")),
        (E.KinematicsError, "reference", lambda: panda.frame_jacobian(q, "panda_hand_tcp", "sideways")),
        (E.KinematicsError, "no_such_frame", lambda: panda.relative_transform(q, "panda_link0", "no_such_frame")),
        (E.KinematicsError, "t is NaN", lambda: panda.interpolate(q, q, NAN)),
        (E.KinematicsError, "nope", lambda: panda.q_from_dict({"nope": 1.0})),
        (E.KinematicsError, "", lambda: panda.q_from_dict({"panda_joint1": [1.0, 2.0]})),
        (E.KinematicsError, "panda_joint1", lambda: panda.q_from_dict({"panda_joint1": "x"})),
        (E.KinematicsError, "one state", lambda: panda.integrate(np.zeros((2, 9)), v)),
        (E.DynamicsError, "v must have shape (9,) or (N, 9)", lambda: panda.rnea(q, np.zeros(3), v)),
        (E.DynamicsError, "tau[0] is NaN", lambda: panda.aba(q, v, np.full(9, NAN))),
        (E.DynamicsError, "a[0] is inf", lambda: panda.rnea(q, v, np.full(9, np.inf))),
        (E.DynamicsError, "stacks 3 states", lambda: panda.rnea(np.zeros((2, 9)), np.zeros((3, 9)), np.zeros((2, 9)))),
        (E.DynamicsError, "q must have shape", lambda: panda.crba(np.zeros(10))),
        (E.DynamicsError, "integrator", lambda: panda.simulate(q, v, integrator="leapfrog")),
        (E.DynamicsError, "dt is inf", lambda: panda.simulate(q, v, dt=np.inf)),
        (E.DynamicsError, "steps", lambda: panda.simulate(q, v, tau=np.zeros((3, 9)), steps=4)),
        (E.DynamicsError, "one initial state", lambda: panda.simulate(np.zeros((2, 9)), v)),
    ]


def test_every_bad_input_raises_its_family(panda):
    cases = catalogue(panda)
    for exc, fragment, call in cases:
        with pytest.raises(exc) as info:
            call()
        assert isinstance(info.value, ValueError)
        assert isinstance(info.value, kinetree.KinetreeError)
        assert fragment in str(info.value), (fragment, str(info.value))
    assert len(cases) >= 30


def test_a_bad_state_in_a_batch_names_the_state(panda):
    q = panda.random_configuration(100, seed=1)
    v = np.zeros((100, 9))
    tau = np.zeros((100, 9))
    tau[57, 4] = np.inf
    with pytest.raises(kinetree.DynamicsError, match=r"tau\[57, 4\] is inf"):
        panda.aba(q, v, tau)


def test_a_bad_number_in_a_large_stack_is_named_as_in_a_small_one(panda):
    """A stack of more than 4 096 numbers is read in place and checked finite by the workers,
    block by block: the error still names the first bad number of the first bad input, whichever
    block hits its bad number first, for every kind of stacked call."""
    n = 3000
    q = panda.random_configuration(n, seed=2)
    v = np.zeros((n, 9))
    a = np.zeros((n, 9))
    q[2900, 1] = np.nan  # a late block of q
    q[1500, 6] = -np.inf  # the first bad number of q
    v[10, 0] = np.nan  # an early block, but of a later argument
    calls = [
        (kinetree.DynamicsError, lambda: panda.rnea(q, v, a)),
        (kinetree.DynamicsError, lambda: panda.aba(q, v, a)),
        (kinetree.DynamicsError, lambda: panda.crba(q)),
        (kinetree.DynamicsError, lambda: panda.nle(q, v)),
        (kinetree.DynamicsError, lambda: panda.rnea_derivatives(q, v, a)),
        (kinetree.DynamicsError, lambda: panda.gravity_derivatives(q)),
        (kinetree.KinematicsError, lambda: panda.link_placements(q)),
        (kinetree.KinematicsError, lambda: panda.frame_jacobian(q, "panda_hand_tcp")),
    ]
    for exc, call in calls:
        with pytest.raises(exc, match=r"^q\[1500, 6\] is -inf: inputs must be finite$"):
            call()
    q[1500, 6] = q[2900, 1] = 0.0
    for exc, call in calls[:2] + calls[3:5]:
        with pytest.raises(exc, match=r"^v\[10, 0\] is NaN: inputs must be finite$"):
            call()
    v[10, 0] = 0.0
    a[2999, 8] = np.inf
    with pytest.raises(kinetree.DynamicsError, match=r"^a\[2999, 8\] is inf"):
        panda.rnea(q, v, a)
    with pytest.raises(kinetree.DynamicsError, match=r"^tau\[2999, 8\] is inf"):
        panda.aba(q, v, a)
    a[2999, 8] = 0.0
    # and once every number is finite, the same stacks compute
    assert panda.rnea(q, v, a).shape == (n, 9)


def test_exception_hierarchy():
    for name in ("ModelError", "KinematicsError", "DynamicsError", "CollisionError", "IkError"):
        cls = getattr(kinetree, name)
        assert issubclass(cls, kinetree.KinetreeError) and issubclass(cls, ValueError)
        assert cls.__module__ == "kinetree"


def test_random_garbage_never_panics(panda, talos):
    """Random shapes, dtypes and values at every per-state method raise only kinetree errors or
    succeed: no PanicException (a BaseException) and no crash."""
    rng = np.random.default_rng(0)
    methods = ["link_placements", "crba", "gravity", "com", "minv", "normalize", "potential_energy"]
    two = ["rnea", "aba"]
    values = [0.0, -1e308, 1e308, 5e-324, 1e6, -1e6]
    for model in (panda, talos):
        for _ in range(300):
            n = int(rng.integers(0, 12))
            width = model.nq if rng.random() < 0.7 else int(rng.integers(0, 45))
            shape = (width,) if rng.random() < 0.5 else (n, width)
            x = rng.choice(values, size=shape) * rng.random(shape)
            try:
                if rng.random() < 0.7:
                    getattr(model, methods[int(rng.integers(len(methods)))])(x)
                else:
                    vv = np.zeros(shape[:-1] + (model.nv,))
                    getattr(model, two[int(rng.integers(2))])(x, vv, vv)
            except kinetree.KinetreeError:
                pass
