"""MJCF models from Python against MuJoCo 4.0's values (tests/data/reference/mjcf): body poses,
the mass matrix, bias forces and inverse dynamics after the documented coordinate mapping, with
the Rust suite's tolerances (poses 1e-9 absolute, the rest 1e-9 relative)."""

import json
import pickle

import numpy as np
import pytest

import kinetree
from conftest import REFERENCE

MJCF = REFERENCE / "mjcf"
NAMES = sorted(p.stem for p in MJCF.glob("*.json"))


def load(name):
    ref = json.loads((MJCF / f"{name}.json").read_text())
    return ref, kinetree.Model.from_mjcf(str(MJCF / ref["xml"]))


def body_name(ref, i):
    return ref["bodies"][i]["name"] or f"body{i}"


def close_rel(ours, theirs, tol=1e-9):
    theirs = np.asarray(theirs, dtype=float)
    scale = max(1.0, np.abs(theirs).max())
    assert np.abs(np.asarray(ours) - theirs).max() <= tol * scale


def test_all_twelve_references_are_here():
    assert len(NAMES) == 12


@pytest.mark.parametrize("name", NAMES)
def test_dynamics_match_mujoco(name):
    ref, model = load(name)
    assert (model.nq, model.nv) == (ref["nq"], ref["nv"])
    links = model.link_names
    for sample in ref["samples"]:
        qpos, qvel, qacc = (np.array(sample[k]) for k in ("qpos", "qvel", "qacc"))
        q = model.q_from_mujoco(qpos)
        np.testing.assert_array_equal(model.q_to_mujoco(q), qpos)
        v = model.v_from_mujoco(qpos, qvel)
        # Inverse dynamics and bias forces, mapped back to MuJoCo's generalized forces.
        a = model.a_from_mujoco(qpos, qvel, qacc)
        close_rel(model.tau_to_mujoco(q, model.rnea(q, v, a)), sample["tau"])
        a0 = model.a_from_mujoco(qpos, qvel, np.zeros(model.nv))
        close_rel(model.tau_to_mujoco(q, model.rnea(q, v, a0)), sample["qfrc_bias"])
        # M in MuJoCo's velocities: G^T M G with v = G qvel (G from the conversion itself).
        g = np.stack([model.v_from_mujoco(qpos, e) for e in np.eye(model.nv)], axis=1)
        close_rel(g.T @ model.crba(q) @ g, sample["M"])
        # Body positions.
        poses = model.link_placements(q)
        xpos = np.array(sample["xpos"])
        for i in range(ref["nbody"]):
            p = poses[links.index(body_name(ref, i))]
            assert np.abs(p[:3, 3] - xpos[i]).max() <= 1e-9


def test_stacked_conversions_and_pickling():
    ref, model = load("gym_ant")
    qpos = np.array([s["qpos"] for s in ref["samples"]])
    qvel = np.array([s["qvel"] for s in ref["samples"]])
    q = model.q_from_mujoco(qpos)
    assert q.shape == qpos.shape
    np.testing.assert_allclose(model.v_to_mujoco(q, model.v_from_mujoco(qpos, qvel)), qvel, atol=1e-14)
    # A free joint's quaternion moves from w-first to w-last.
    np.testing.assert_array_equal(q[:, 3:7], qpos[:, [4, 5, 6, 3]])
    back = pickle.loads(pickle.dumps(model))
    np.testing.assert_allclose(back.crba(q[0]), model.crba(q[0]), rtol=0, atol=1e-15)


def test_text_load_and_errors():
    xml = '<mujoco><worldbody><body name="b"><joint name="j" type="slide"/><geom size="0.1" mass="2"/></body></worldbody></mujoco>'
    m = kinetree.Model.from_mjcf(xml)
    assert m.nq == 1 and m.total_mass == pytest.approx(2.0)
    np.testing.assert_allclose(m.crba([0.0]), [[2.0]])
    with pytest.raises(kinetree.ModelError, match="unknown joint type"):
        kinetree.Model.from_mjcf('<mujoco><worldbody><body><joint type="twist"/></body></worldbody></mujoco>')
    with pytest.raises(kinetree.ModelError, match="qpos"):
        m.q_from_mujoco([0.0, 1.0])
    with pytest.raises(kinetree.ModelError, match="floating"):
        kinetree.Model.load(str(MJCF / "models/gym_hopper/hopper.xml"), floating=True)


def test_sdformat_loads_like_drake():
    """Drake's acrobot: the two revolute joints, and its mass matrix at q = 0 (Drake's value)."""
    ref = json.loads((REFERENCE / "sdf" / "drake" / "Acrobot.json").read_text())
    path = REFERENCE / "sdf" / "drake" / "models" / "examples" / "acrobot" / "Acrobot.sdf"
    model = kinetree.Model.from_sdf(str(path))
    assert model.nq == 2 and kinetree.Model.load(str(path)).nq == 2
    sample = ref["samples"][0]
    # Drake names positions <model>_<joint>_q.
    q = model.q_from_dict({n[len("Acrobot_"):-len("_q")]: x for n, x in zip(ref["position_names"], sample["q"])})
    close_rel(model.crba(q), sample["mass_matrix"])
    with pytest.raises(kinetree.ModelError):
        kinetree.Model.from_sdf('<sdf version="1.7"><model name="m"><joint name="j" type="screw"/></model></sdf>')
