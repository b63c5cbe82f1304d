"""Every quantity against Pinocchio 4.1's values in tests/data/reference, with the tolerances of
the Rust regression suite: poses and Jacobians 1e-9 absolute, the rest 1e-9 relative to the
largest reference entry (ABA: relative to max(1e-9, 1e-13 * cond(M)))."""

import json

import numpy as np
import pytest

import kinetree
from conftest import REFERENCE

ROBOTS = ["double_pendulum", "ur5", "kinova", "panda", "solo12", "talos_reduced"]


def load(robot):
    ref = json.loads((REFERENCE / f"{robot}.json").read_text())
    model = kinetree.Model.from_urdf(
        str(REFERENCE / ref["urdf"]), floating=ref["root_joint"] != "fixed"
    )
    # Pinocchio's v order -> ours, by joint name.
    ours = {j.name: j for j in model.joints}
    perm = np.zeros(model.nv, dtype=int)
    for j in ref["joints"]:
        o = ours[j["name"]]
        assert o.nv == j["nv"]
        perm[o.idx_v : o.idx_v + o.nv] = np.arange(j["idx_v"], j["idx_v"] + j["nv"])
    return ref, model, perm


def state(model, sample, key):
    values = sample["state"].get(key)
    if values is None:
        return None
    return model.q_from_dict(values) if key == "q" else model.v_from_dict(values)


def close_rel(ours, theirs, tol=1e-9):
    theirs = np.asarray(theirs, dtype=float)
    scale = max(np.abs(theirs).max(), 0.0)
    err = np.abs(np.asarray(ours) - theirs).max()
    assert err <= tol * (scale if scale > 0 else 1.0), (err, scale)


@pytest.mark.parametrize("robot", ROBOTS)
def test_every_quantity_matches_pinocchio(robot):
    ref, model, perm = load(robot)
    assert (model.nq, model.nv) == (ref["nq"], ref["nv"]) or robot == "kinova"
    names = model.link_names
    checked = 0
    for sample in ref["samples"]:
        q, v, a, tau = (state(model, sample, k) for k in ("q", "v", "a", "tau"))
        poses = model.link_placements(q)
        for link, pose in sample["link_poses"].items():
            got = poses[names.index(link)]
            np.testing.assert_allclose(got[:3, 3], pose["translation"], rtol=0, atol=1e-9)
            np.testing.assert_allclose(got[:3, :3], pose["rotation"], rtol=0, atol=1e-9)
            np.testing.assert_array_equal(got[3], [0, 0, 0, 1])
        for link, jac in sample["jacobians"].items():
            got = model.frame_jacobian(q, link, "local_world_aligned")
            np.testing.assert_allclose(got, np.asarray(jac)[:, perm], rtol=0, atol=1e-9)
        close_rel(model.rnea(q, v, a), np.asarray(sample["rnea"])[perm])
        close_rel(model.nle(q, v), np.asarray(sample["nle"])[perm])
        close_rel(model.gravity(q), np.asarray(sample["gravity_torque"])[perm])
        M = model.crba(q)
        close_rel(M, np.asarray(sample["mass_matrix"])[np.ix_(perm, perm)])
        assert (M == M.T).all()
        if sample.get("aba") is not None:
            tol = max(1e-9, 1e-13 * sample["mass_matrix_cond"])
            close_rel(model.aba(q, v, tau), np.asarray(sample["aba"])[perm], tol)
        close_rel(model.com(q), sample["com"])
        close_rel(model.kinetic_energy(q, v), sample["kinetic_energy"])
        close_rel(model.centroidal_momentum(q, v), sample["centroidal_momentum"])
        checked += 1
    assert checked == len(ref["samples"]) > 0


@pytest.mark.parametrize("robot", ["panda", "talos_reduced"])
def test_identities_between_quantities(robot):
    """M·a + nle = rnea; aba inverts rnea; minv inverts M; KE = ½ vᵀMv."""
    _, model, _ = load(robot)
    rng = np.random.default_rng(3)
    q = model.random_configuration(20, seed=5)
    v = rng.uniform(-1, 1, (20, model.nv))
    a = rng.uniform(-1, 1, (20, model.nv))
    M = model.crba(q)
    tau = model.rnea(q, v, a)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", M, a) + model.nle(q, v), tau, atol=1e-9)
    np.testing.assert_allclose(model.aba(q, v, tau), a, atol=1e-8)
    np.testing.assert_allclose(model.minv(q) @ M, np.broadcast_to(np.eye(model.nv), M.shape), atol=1e-8)
    ke = 0.5 * np.einsum("ni,nij,nj->n", v, M, v)
    np.testing.assert_allclose(model.kinetic_energy(q, v), ke, rtol=1e-10)


def test_frame_jacobian_is_the_derivative_of_the_pose(panda):
    """Central differences of the hand's pose along each joint give the Jacobian's columns."""
    q = panda.random_configuration(seed=11)
    J = panda.frame_jacobian(q, "panda_hand_tcp", "local_world_aligned")
    R0 = panda.frame_placement(q, "panda_hand_tcp")[:3, :3]
    h = 1e-6
    for k in range(panda.nv):
        dq = np.zeros(panda.nv)
        dq[k] = h
        plus = panda.frame_placement(panda.integrate(q, dq), "panda_hand_tcp")
        minus = panda.frame_placement(panda.integrate(q, -dq), "panda_hand_tcp")
        np.testing.assert_allclose((plus[:3, 3] - minus[:3, 3]) / (2 * h), J[:3, k], atol=1e-8)
        dR = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ R0.T
        omega = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
        np.testing.assert_allclose(omega, J[3:, k], atol=1e-7)


def test_jacobian_references_and_velocity_agree(panda):
    q = panda.random_configuration(seed=2)
    v = np.linspace(-1, 1, panda.nv)
    for ref in ("world", "local", "local_world_aligned"):
        J = panda.frame_jacobian(q, "panda_hand_tcp", ref)
        np.testing.assert_allclose(J @ v, panda.frame_velocity(q, v, "panda_hand_tcp", ref), atol=1e-12)
    # d/dt (J v) with a = 0 is dJ/dt v: the frame's spatial acceleration.
    for ref in ("world", "local", "local_world_aligned"):
        dJ = panda.frame_jacobian_time_variation(q, v, "panda_hand_tcp", ref)
        acc = panda.frame_acceleration(q, v, np.zeros(panda.nv), "panda_hand_tcp", ref)
        if ref != "local_world_aligned":  # LWA's derivative also turns the axes
            np.testing.assert_allclose(dJ @ v, acc, atol=1e-10)


def test_frame_jacobian_time_variation_by_differences(panda):
    q = panda.random_configuration(seed=4)
    v = np.linspace(-1, 1, panda.nv)
    h = 1e-6
    for ref in ("world", "local", "local_world_aligned"):
        dJ = panda.frame_jacobian_time_variation(q, v, "panda_hand_tcp", ref)
        jp = panda.frame_jacobian(panda.integrate(q, h * v), "panda_hand_tcp", ref)
        jm = panda.frame_jacobian(panda.integrate(q, -h * v), "panda_hand_tcp", ref)
        np.testing.assert_allclose((jp - jm) / (2 * h), dJ, atol=1e-7)


def test_relative_transform_composes(panda):
    q = panda.random_configuration(seed=9)
    a = panda.frame_placement(q, "panda_link3")
    b = panda.frame_placement(q, "panda_hand_tcp")
    np.testing.assert_allclose(panda.relative_transform(q, "panda_link3", "panda_hand_tcp"), np.linalg.inv(a) @ b, atol=1e-12)
