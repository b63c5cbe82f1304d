"""The ``out=`` parameter: results written into the caller's array equal the returned ones bit
for bit, and a wrong ``out`` is refused with the family's error naming the expected shape."""

import numpy as np
import pytest

import kinetree

# name -> (inputs as a function of (model, q, v, a), shape of one state's result)
CALLS = {
    "link_placements": (lambda m, q, v, a: (q,), lambda m: (len(m.link_names), 4, 4)),
    "frame_jacobian": (lambda m, q, v, a: (q, m.link_names[-1], "local"), lambda m: (6, m.nv)),
    "rnea": (lambda m, q, v, a: (q, v, a), lambda m: (m.nv,)),
    "crba": (lambda m, q, v, a: (q,), lambda m: (m.nv, m.nv)),
    "aba": (lambda m, q, v, a: (q, v, a), lambda m: (m.nv,)),
}
ERRORS = {
    "link_placements": kinetree.KinematicsError,
    "frame_jacobian": kinetree.KinematicsError,
    "rnea": kinetree.DynamicsError,
    "crba": kinetree.DynamicsError,
    "aba": kinetree.DynamicsError,
}


def states(model, n, seed=0):
    rng = np.random.default_rng(seed)
    return (model.random_configuration(n, seed=seed), rng.uniform(-1, 1, (n, model.nv)),
            rng.uniform(-1, 1, (n, model.nv)))


@pytest.mark.parametrize("method", sorted(CALLS))
@pytest.mark.parametrize("robot", ["panda", "talos"])
# one state, a stack run inline, a parallel stack (copied), a stack read in place (> 4096 numbers)
@pytest.mark.parametrize("n", [None, 3, 64, 600])
def test_out_equals_the_returned_result(method, robot, n, request):
    model = request.getfixturevalue(robot)
    args_of, shape_of = CALLS[method]
    q, v, a = states(model, 1 if n is None else n)
    if n is None:
        q, v, a = q[0], v[0], a[0]
    args = args_of(model, q, v, a)
    expected = getattr(model, method)(*args)
    shape = shape_of(model) if n is None else (n, *shape_of(model))
    out = np.full(shape, np.nan)
    got = getattr(model, method)(*args, out=out)
    assert got is out
    assert np.array_equal(out, expected)  # bit for bit
    # a second call overwrites every entry
    out[...] = 7.0
    getattr(model, method)(*args, out=out)
    assert np.array_equal(out, expected)


def test_out_may_be_an_input(panda):
    q, v, a = (x[0] for x in states(panda, 1))
    tau = panda.rnea(q, v, a)
    panda.rnea(q, v, a, out=v)  # the inputs are read before the result is written
    assert np.array_equal(v, tau)


@pytest.mark.parametrize("n", [64, 600])  # inputs copied, inputs read in place
def test_a_stacked_out_may_share_memory_with_an_input(n, panda):
    Q, V, A = states(panda, n)
    expected = panda.rnea(Q, V, A)
    # out is an input
    v = V.copy()
    assert panda.rnea(Q, v, A, out=v) is v
    assert np.array_equal(v, expected)
    # out overlaps half of an input, shifted by half a stack: every state reads its own inputs
    memory = np.zeros((n + n // 2, panda.nv))
    memory[:n] = V
    out = memory[n // 2:]
    panda.rnea(Q, memory[:n], A, out=out)
    assert np.array_equal(out, expected)
    # the same for CRBA, whose results are larger than its inputs
    M = panda.crba(Q)
    memory = np.zeros(n * panda.nv * panda.nv)
    memory[:Q.size] = Q.ravel()
    out = memory.reshape(n, panda.nv, panda.nv)
    panda.crba(memory[:Q.size].reshape(Q.shape), out=out)
    assert np.array_equal(out, M)


@pytest.mark.parametrize("method", sorted(CALLS))
def test_a_stack_read_in_place_equals_one_state_at_a_time(method, talos):
    """A large stack (read in place, not copied) gives every state its one-state result, also
    when the stack is a strided view (copied) or a slice of a larger array (read in place)."""
    args_of, _ = CALLS[method]
    Q, V, A = states(talos, 400)
    one = np.array([getattr(talos, method)(*args_of(talos, q, v, a)) for q, v, a in zip(Q, V, A)])
    assert np.array_equal(getattr(talos, method)(*args_of(talos, Q, V, A)), one)
    strided = [np.repeat(x, 2, axis=0)[::2] for x in (Q, V, A)]
    assert not strided[0].flags.c_contiguous
    assert np.array_equal(getattr(talos, method)(*args_of(talos, *strided)), one)
    inner = [np.vstack([x, x])[len(Q):] for x in (Q, V, A)]
    assert np.array_equal(getattr(talos, method)(*args_of(talos, *inner)), one)


@pytest.mark.parametrize("method", sorted(CALLS))
def test_a_wrong_out_is_refused(method, panda):
    args_of, shape_of = CALLS[method]
    q, v, a = (x[0] for x in states(panda, 1))
    args = args_of(panda, q, v, a)
    shape = shape_of(panda)
    wanted = "out must be a C-contiguous, writeable float64 numpy array of shape " + (
        f"({shape[0]},)" if len(shape) == 1 else "(" + ", ".join(map(str, shape)) + ")")
    error = ERRORS[method]
    fortran = np.zeros((*shape, 2), order="F")[..., 0] if len(shape) > 1 else np.zeros(2 * shape[0])[::2]
    readonly = np.zeros(shape)
    readonly.flags.writeable = False
    bad = {
        "a stacked shape for one state": (np.zeros((1, *shape)), "got shape"),
        "a wrong shape": (np.zeros(shape[:-1] + (shape[-1] + 1,)), "got shape"),
        "float32": (np.zeros(shape, dtype=np.float32), "got an array of dtype float32"),
        "int64": (np.zeros(shape, dtype=np.int64), "got an array of dtype int64"),
        "a list": (np.zeros(shape).tolist(), "got a list"),
        "a strided view": (fortran, "got a non-contiguous view"),
        "a read-only array": (readonly, "out cannot be written"),
    }
    for what, (out, message) in bad.items():
        with pytest.raises(error, match=message) as info:
            getattr(panda, method)(*args, out=out)
        assert isinstance(info.value, ValueError), what
        if "cannot be written" not in message:
            assert wanted in str(info.value), what
        else:
            assert "pass a writeable float64 array of shape" in str(info.value), what
    # a stack needs the stacked shape
    Q, V, A = states(panda, 4)
    with pytest.raises(error, match=r"of shape \(4, "):
        getattr(panda, method)(*args_of(panda, Q, V, A), out=np.zeros(shape))
    # a bad input is refused as without out
    out = np.zeros(shape)
    with pytest.raises(error):
        getattr(panda, method)(*args_of(panda, np.full_like(q, np.nan), v, a), out=out)


# name -> (inputs as a function of (q, v, a), number of results)
DERIVATIVES = {
    "rnea_derivatives": (lambda q, v, a: (q, v, a), 3),
    "aba_derivatives": (lambda q, v, a: (q, v, a), 3),
    "gravity_derivatives": (lambda q, v, a: (q,), 1),
}


@pytest.mark.parametrize("method", sorted(DERIVATIVES))
@pytest.mark.parametrize("n", [None, 3, 64, 600])
def test_derivatives_into_out_equal_the_returned_ones(method, n, panda):
    args_of, parts = DERIVATIVES[method]
    q, v, a = states(panda, 1 if n is None else n)
    if n is None:
        q, v, a = q[0], v[0], a[0]
    expected = getattr(panda, method)(*args_of(q, v, a))
    expected = expected if parts > 1 else (expected,)
    shape = (panda.nv, panda.nv) if n is None else (n, panda.nv, panda.nv)
    out = tuple(np.full(shape, np.nan) for _ in range(parts))
    got = getattr(panda, method)(*args_of(q, v, a), out=out if parts > 1 else out[0])
    got = got if parts > 1 else (got,)
    for g, o, e in zip(got, out, expected):
        assert g is o
        assert np.array_equal(o, e)  # bit for bit


@pytest.mark.parametrize("method", sorted(DERIVATIVES))
def test_derivatives_out_may_share_memory_with_a_stacked_input(method, panda):
    """An input stack read in place and overlapping a result is copied before the results are
    written (600 states: more than 4 096 numbers, read in place)."""
    args_of, parts = DERIVATIVES[method]
    n, nv = 600, panda.nv
    Q, V, A = states(panda, n)
    expected = getattr(panda, method)(*args_of(Q, V, A))
    expected = expected if parts > 1 else (expected,)
    memory = np.zeros(n * nv * nv)
    memory[:Q.size] = Q.ravel()
    out = (memory.reshape(n, nv, nv),) + tuple(np.empty((n, nv, nv)) for _ in range(parts - 1))
    getattr(panda, method)(*args_of(memory[:Q.size].reshape(Q.shape), V, A),
                           out=out if parts > 1 else out[0])
    for o, e in zip(out, expected):
        assert np.array_equal(o, e)


@pytest.mark.parametrize("method", ["rnea_derivatives", "aba_derivatives"])
def test_a_wrong_derivatives_out_is_refused(method, panda):
    args_of, _ = DERIVATIVES[method]
    q, v, a = (x[0] for x in states(panda, 1))
    nv = panda.nv
    ok = [np.zeros((nv, nv)) for _ in range(3)]
    readonly = np.zeros((nv, nv))
    readonly.flags.writeable = False
    bad = {
        "one array": (np.zeros((nv, nv)), "out must be a tuple of 3"),
        "two arrays": (tuple(ok[:2]), "out must be a tuple of 3"),
        "the same array twice": ((ok[0], ok[1], ok[0]), r"out\[0\] and out\[2\] share memory"),
        "a wrong shape": ((ok[0], np.zeros((nv, nv + 1)), ok[2]), f"of shape \\({nv}, {nv}\\)"),
        "float32": ((ok[0], ok[1], np.zeros((nv, nv), dtype=np.float32)), "dtype float32"),
        "a read-only array": ((ok[0], readonly, ok[2]), "cannot be written"),
    }
    for what, (out, message) in bad.items():
        with pytest.raises(kinetree.DynamicsError, match=message) as info:
            getattr(panda, method)(*args_of(q, v, a), out=out)
        assert isinstance(info.value, ValueError), what
    # views of one array that overlap are refused
    memory = np.zeros(3 * nv * nv)
    views = (memory[:nv * nv].reshape(nv, nv), memory[nv:nv + nv * nv].reshape(nv, nv),
             memory[2 * nv * nv:].reshape(nv, nv))
    with pytest.raises(kinetree.DynamicsError, match=r"out\[0\] and out\[1\] share memory"):
        getattr(panda, method)(*args_of(q, v, a), out=views)
    # a list is accepted as a tuple
    lst = [np.zeros((nv, nv)) for _ in range(3)]
    got = getattr(panda, method)(*args_of(q, v, a), out=lst)
    assert all(g is o for g, o in zip(got, lst))
