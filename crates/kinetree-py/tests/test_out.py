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
