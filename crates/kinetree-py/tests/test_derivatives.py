"""The analytic derivatives against Pinocchio 4.1's computeRNEADerivatives,
computeGeneralizedGravityDerivatives and computeABADerivatives (tests/data/reference/derivatives,
1e-8 relative to the matrix's largest entry as in the Rust tests; ABA scaled by cond(M)/1e3), and
against central finite differences through integrate; stacks equal one-by-one calls."""

import json

import numpy as np
import pytest

import kinetree
from conftest import REFERENCE

ROBOTS = ["double_pendulum", "ur5", "kinova", "panda", "solo12", "talos_reduced"]


def load(robot):
    ref = json.loads((REFERENCE / "derivatives" / f"{robot}.json").read_text())
    main = json.loads((REFERENCE / f"{robot}.json").read_text())
    model = kinetree.Model.from_urdf(
        str(REFERENCE / "derivatives" / ref["urdf"]), floating=ref["root_joint"] != "fixed"
    )
    # perm[ours] = theirs: our v index of each of Pinocchio's, by joint name.
    ours = {j.name: j for j in model.joints}
    perm = np.zeros(model.nv, dtype=int)
    for j in ref["joints"]:
        o = ours[j["name"]]
        perm[o.idx_v : o.idx_v + o.nv] = np.arange(j["idx_v"], j["idx_v"] + j["nv"])
    return ref, main, model, perm


def close(ours, theirs, perm, tol):
    theirs = np.asarray(theirs, dtype=float)
    mine = np.empty_like(theirs)
    mine[np.ix_(perm, perm)] = ours
    err = np.abs(mine - theirs).max()
    assert err <= tol * max(1.0, np.abs(theirs).max()), (err, np.abs(theirs).max())


@pytest.mark.parametrize("robot", ROBOTS)
def test_derivatives_match_pinocchio(robot):
    ref, main, model, perm = load(robot)
    checked = 0
    for i, sample in enumerate(ref["samples"]):
        st = sample["state"]
        q = model.q_from_dict(st["q"])
        v, a, tau = (model.v_from_dict(st[k]) for k in ("v", "a", "tau"))
        for ours, key in zip(model.rnea_derivatives(q, v, a), ("dtau_dq", "dtau_dv", "dtau_da")):
            close(ours, sample["rnea"][key], perm, 1e-8)
            checked += 1
        close(model.gravity_derivatives(q), sample["gravity"]["dg_dq"], perm, 1e-8)
        checked += 1
        if sample["aba"] is None:
            continue
        tol = 1e-8 * max(1.0, main["samples"][i]["mass_matrix_cond"] / 1e3)
        for ours, key in zip(model.aba_derivatives(q, v, tau), ("dddq_dq", "dddq_dv", "dddq_dtau")):
            close(ours, sample["aba"][key], perm, tol)
            checked += 1
    assert checked >= 4 * len(ref["samples"])


def test_derivatives_match_finite_differences(talos):
    model = talos
    rng = np.random.default_rng(3)
    q = model.random_configuration(seed=11)
    v, a, tau = (rng.uniform(-1, 1, model.nv) for _ in range(3))
    h = 1e-6
    dq, dv, M = model.rnea_derivatives(q, v, a)
    ddq_dq, ddq_dv, minv = model.aba_derivatives(q, v, tau)
    dg = model.gravity_derivatives(q)
    fd = {name: np.zeros((model.nv, model.nv)) for name in ("rq", "rv", "aq", "av", "g")}
    for k in range(model.nv):
        e = np.zeros(model.nv)
        e[k] = h
        qp, qm = model.integrate(q, e), model.integrate(q, -e)
        fd["rq"][:, k] = (model.rnea(qp, v, a) - model.rnea(qm, v, a)) / (2 * h)
        fd["rv"][:, k] = (model.rnea(q, v + e, a) - model.rnea(q, v - e, a)) / (2 * h)
        fd["aq"][:, k] = (model.aba(qp, v, tau) - model.aba(qm, v, tau)) / (2 * h)
        fd["av"][:, k] = (model.aba(q, v + e, tau) - model.aba(q, v - e, tau)) / (2 * h)
        fd["g"][:, k] = (model.gravity(qp) - model.gravity(qm)) / (2 * h)
    for ours, name in [(dq, "rq"), (dv, "rv"), (ddq_dq, "aq"), (ddq_dv, "av"), (dg, "g")]:
        scale = max(1.0, np.abs(fd[name]).max())
        assert np.abs(ours - fd[name]).max() <= 1e-5 * scale, name
    np.testing.assert_allclose(M, model.crba(q), rtol=0, atol=1e-12 * np.abs(M).max())
    np.testing.assert_allclose(minv @ M, np.eye(model.nv), atol=1e-9)
    # ∂q̈/∂q = -M⁻¹ ∂τ/∂q at a = q̈.
    dq_at, _, _ = model.rnea_derivatives(q, v, model.aba(q, v, tau))
    np.testing.assert_allclose(ddq_dq, -minv @ dq_at, atol=1e-8 * max(1.0, np.abs(ddq_dq).max()))


@pytest.mark.parametrize("method", ["rnea_derivatives", "gravity_derivatives", "aba_derivatives"])
@pytest.mark.parametrize("n", [0, 3, 16])  # empty, a stack run inline, a parallel stack
def test_stacked_derivatives_equal_one_by_one(method, n, talos):
    model = talos
    rng = np.random.default_rng(5)
    q = model.random_configuration(n, seed=2)
    v, a = rng.uniform(-1, 1, (n, model.nv)), rng.uniform(-1, 1, (n, model.nv))
    args = (q,) if method == "gravity_derivatives" else (q, v, a)
    stacked = getattr(model, method)(*args)
    stacked = stacked if isinstance(stacked, tuple) else (stacked,)
    for part in stacked:
        assert part.shape == (n, model.nv, model.nv)
    for i in range(n):
        one = getattr(model, method)(*(x[i] for x in args))
        one = one if isinstance(one, tuple) else (one,)
        for s, o in zip(stacked, one):
            assert np.array_equal(s[i], o)  # bit for bit


def test_derivative_errors_name_the_input(panda):
    with pytest.raises(kinetree.DynamicsError, match=r"v must have shape \(9,\)"):
        panda.rnea_derivatives(panda.neutral(), np.zeros(3), np.zeros(9))
    with pytest.raises(kinetree.DynamicsError, match="finite"):
        panda.aba_derivatives(panda.neutral(), np.zeros(9), np.full(9, np.nan))
    with pytest.raises(kinetree.DynamicsError, match="stack"):
        panda.aba_derivatives(np.stack([panda.neutral()] * 2), np.zeros(9), np.zeros((2, 9)))


@pytest.mark.parametrize("n", [12, 40])
def test_a_failing_state_of_a_stack_is_named(n, panda):
    q = panda.random_configuration(n, seed=1)
    v, a = np.zeros((n, 9)), np.zeros((n, 9))
    v[11] = 1e200  # finite, but tau overflows
    for method in ("rnea_derivatives", "aba_derivatives"):
        with pytest.raises(kinetree.DynamicsError, match=r"^state 11: (tau|ddq) overflowed at joint .panda_joint1."):
            getattr(panda, method)(q, v, a)
    v[11] = 0.0
    for part in panda.rnea_derivatives(q, v, a):
        assert part.shape == (n, 9, 9) and np.isfinite(part).all()


def test_a_stack_with_several_failing_states_names_the_lowest(panda):
    # The blocks run on the calling thread and on the workers in whatever order they take
    # them; the error is still the lowest failing state's, every time.
    n = 2000
    q = panda.random_configuration(n, seed=2)
    v, a = np.zeros((n, 9)), np.zeros((n, 9))
    v[[37, 1500, 1999]] = 1e200
    for method in ("rnea_derivatives", "aba_derivatives", "rnea", "aba"):
        for _ in range(5):
            with pytest.raises(kinetree.DynamicsError, match=r"^state 37: "):
                getattr(panda, method)(q, v, a)
