"""IK, workspace sampling and collision from Python: reference IK targets, batch == one-by-one,
voxel maps, and per-link-pair distances against coal (the reference's 1e-6)."""

import json
import pickle

import numpy as np
import pytest

import kinetree
from conftest import REFERENCE


def reference(robot):
    ref = json.loads((REFERENCE / f"{robot}.json").read_text())
    return ref, kinetree.Model.from_urdf(str(REFERENCE / ref["urdf"]))


def pose(p):
    m = np.eye(4)
    m[:3, :3] = p["rotation"]
    m[:3, 3] = p["translation"]
    return m


@pytest.mark.parametrize("robot", ["ur5", "panda"])
def test_ik_reaches_the_reference_targets(robot):
    ref, model = reference(robot)
    targets = ref["ik_targets"]
    frame = targets["ee_link"]
    ik = kinetree.IkSolver(model, time_budget=None, seed=0)
    goals = []
    for t in targets["targets"]:
        goal = pose(t["pose"] if "pose" in t else t)
        goals.append(goal)
        q, report = ik.solve(frame, goal)
        assert report.converged and report.status == "converged", report
        assert report.position_error < 1e-6 and report.orientation_error < 1e-5
        reached = model.frame_placement(q, frame)
        np.testing.assert_allclose(reached[:3, 3], goal[:3, 3], atol=1e-6)
        np.testing.assert_allclose(reached[:3, :3], goal[:3, :3], atol=2e-5)
        assert ((q >= model.lower_limits - 1e-12) & (q <= model.upper_limits + 1e-12)).all()
    qs, info = ik.solve_batch(frame, np.array(goals))
    assert all(info["converged"])
    for i, goal in enumerate(goals):
        q, _ = ik.solve(frame, goal)
        assert np.array_equal(qs[i], q)  # same seed, no time budget: the same solve


def test_ik_position_only_weights_posture_and_several_targets(panda):
    ik = kinetree.IkSolver(panda, time_budget=None)
    point = np.array([0.4, 0.2, 0.5])
    q, report = ik.solve("panda_hand_tcp", point)
    assert report.converged
    np.testing.assert_allclose(panda.frame_placement(q, "panda_hand_tcp")[:3, 3], point, atol=1e-6)
    # weights: only z matters
    height = np.eye(4)
    height[2, 3] = 0.7
    q, report = ik.solve("panda_hand_tcp", height, weights=[0, 0, 1, 0, 0, 0])
    assert report.converged
    assert panda.frame_placement(q, "panda_hand_tcp")[2, 3] == pytest.approx(0.7, abs=1e-6)
    # two frames at once
    q_goal = panda.random_configuration(seed=5)
    a = panda.frame_placement(q_goal, "panda_hand_tcp")
    b = panda.frame_placement(q_goal, "panda_link4")[:3, 3]
    q, report = ik.solve_targets([("panda_hand_tcp", a), ("panda_link4", b, [1, 1, 1, 0, 0, 0])])
    assert report.converged
    np.testing.assert_allclose(panda.frame_placement(q, "panda_link4")[:3, 3], b, atol=1e-6)
    # only some joints move
    ik.set_moving_joints(["panda_joint1"])
    q0 = panda.neutral()
    q, report = ik.solve("panda_hand_tcp", point, q0=q0)
    assert np.array_equal(q[1:], q0[1:])
    ik.set_moving_joints(None)
    # a posture changes which solution of the redundant arm is found, never convergence
    ik.set_posture(panda.q_from_dict({"panda_joint3": 1.0}), gain=0.5)
    q, report = ik.solve("panda_hand_tcp", point)
    assert report.converged


def test_ik_errors(panda):
    ik = kinetree.IkSolver(panda)
    for call, fragment in [
        (lambda: ik.solve("nope", np.eye(4)), "nope"),
        (lambda: ik.solve("panda_hand_tcp", np.zeros((2, 2))), "shape"),
        (lambda: ik.solve("panda_hand_tcp", np.full(3, np.nan)), "finite"),
        (lambda: ik.solve("panda_hand_tcp", np.ones((4, 4))), "last row"),
        (lambda: ik.solve("panda_hand_tcp", np.diag([2.0, 1.0, 1.0, 1.0])), ""),  # not a rotation
        (lambda: ik.solve("panda_hand_tcp", [0.4, 0, 0.5], q0=np.zeros(3)), "q0"),
        (lambda: ik.solve("panda_hand_tcp", [0.4, 0, 0.5], weights=[-1, 0, 0, 0, 0, 0]), ""),
        (lambda: ik.set_moving_joints(["nope"]), "nope"),
        (lambda: kinetree.IkSolver(panda, position_tolerance=np.nan), "position_tolerance"),
        (lambda: kinetree.IkSolver(panda, time_budget=-1.0), "time_budget"),
        (lambda: ik.solve_batch("panda_hand_tcp", np.zeros((3, 3)), q0=np.zeros((2, 9))), "q0"),
    ]:
        with pytest.raises(kinetree.IkError) as info:
            call()
        assert fragment in str(info.value)


def test_workspace_sampling_and_voxels(panda):
    ws = panda.sample_workspace("panda_hand_tcp", samples=5000, seed=3)
    assert len(ws) == 5000 and ws.positions.shape == (5000, 3) and ws.orientations is None
    assert ws.frame == "panda_hand_tcp" and ws.joints[0] == "panda_joint1"
    # the samples are forward kinematics of configurations within the limits: within reach
    lo, hi = ws.bounds()
    assert (ws.positions >= lo).all() and (ws.positions <= hi).all()
    reach = ws.max_reach([0, 0, 0.333])
    assert reach == pytest.approx(np.linalg.norm(ws.positions - [0, 0, 0.333], axis=1).max())
    again = panda.sample_workspace("panda_hand_tcp", samples=5000, seed=3)
    assert np.array_equal(again.positions, ws.positions)  # the same seed, the same samples
    vox = ws.voxelize(0.1)
    idx, counts, vmax, vmean = vox.voxels()
    assert counts.sum() == 5000 and len(vox) == len(idx)
    assert vox.volume == pytest.approx(len(vox) * 0.1**3)
    assert vox.is_reachable(ws.positions[0])
    hits = vox.is_reachable(ws.positions)
    assert hits.dtype == bool and hits.all()
    assert not vox.is_reachable([5.0, 0, 0]) and not vox.is_reachable([np.nan, 0, 0])
    assert pickle.loads(pickle.dumps(vox)) == vox
    pose_ws = panda.sample_workspace("panda_hand_tcp", samples=100, seed=1, task="pose")
    np.testing.assert_allclose(np.linalg.norm(pose_ws.orientations, axis=1), 1.0, atol=1e-12)
    grid = panda.sample_workspace("panda_link2", grid=5)
    assert len(grid) == 5 ** len(grid.joints)
    with pytest.raises(kinetree.KinematicsError):
        ws.voxelize(0.0)
    with pytest.raises(kinetree.KinematicsError):
        vox.merge(ws.voxelize(0.2))
    with pytest.raises(kinetree.KinematicsError):
        panda.sample_workspace("panda_hand_tcp", samples=10, grid=3)


def test_link_pair_distances_match_coal():
    ref, model = reference("panda_collision")
    cm = kinetree.CollisionModel(model)
    checked = 0
    for sample in ref["samples"]:
        q = model.q_from_dict(sample["state"]["q"])
        ours = cm.link_pair_distances(q)
        theirs = {(c["link_a"], c["link_b"]): c["distance"] for c in sample["collision"]}
        assert set(ours) == set(theirs)
        for pair, d in theirs.items():
            assert ours[pair] == pytest.approx(d, abs=1e-6)
            checked += 1
        assert cm.any_collision(q) == (min(theirs.values()) < 0)
    assert checked > 100


def test_distance_tolerance():
    model = kinetree.Model.from_urdf(str(REFERENCE / "urdf" / "panda_collision.urdf"))
    cm = kinetree.CollisionModel(model)
    assert cm.distance_tolerance == 1e-8
    # Separated cylinder pairs are solved to round-off whatever the tolerance; at this pose an
    # overlap between link 5 and the hand still goes through EPA, where the tolerance applies.
    q = model.q_from_dict({"panda_joint4": -0.3})
    fine = [d["distance"] for d in cm.distances(q)]
    for bad in (0.0, 1e-13, 1e-2, float("nan"), float("inf"), -1e-8):
        with pytest.raises(kinetree.CollisionError, match="distance tolerance"):
            cm.set_distance_tolerance(bad)
        assert cm.distance_tolerance == 1e-8
    cm.set_distance_tolerance(1e-6)
    assert cm.distance_tolerance == 1e-6
    coarse = [d["distance"] for d in cm.distances(q)]
    # Both are upper bounds of the exact distance d*, with 0 <= d - d* <= tol * max(|d|, 1 mm).
    changed = 0
    for f, c in zip(fine, coarse):
        scale = max(abs(f), 1e-3)
        assert -1e-8 * scale - 1e-12 <= c - f <= 1e-6 * scale + 1e-12
        changed += c != f
    assert changed > 0
    cm.set_distance_tolerance(1e-8)
    assert [d["distance"] for d in cm.distances(q)] == fine


def test_collision_queries(panda):
    model = kinetree.Model.from_urdf(str(REFERENCE / "urdf" / "panda_collision.urdf"))
    cm = kinetree.CollisionModel(model)
    q = model.neutral()
    contacts = cm.collisions(q)
    assert contacts and all(c["distance"] <= 0 for c in contacts)
    dist = cm.distances(q)
    assert len(dist) == cm.npairs
    for d in dist[:20]:
        # the witness points are as far apart as the distance (signed)
        gap = np.linalg.norm(d["point_b"] - d["point_a"])
        assert gap == pytest.approx(abs(d["distance"]), abs=1e-9)
        assert np.linalg.norm(d["normal"]) == pytest.approx(1.0)
    Q = model.random_configuration(50, seed=4)
    batch = cm.any_collision(Q)
    assert batch.dtype == bool and list(batch) == [cm.any_collision(x) for x in Q]
    # an obstacle at the hand
    hand = model.frame_placement(q, "panda_link7")
    ball = np.eye(4)
    ball[:3, 3] = hand[:3, 3]
    assert cm.add_obstacle("ball", "sphere", [0.05], ball) == 0
    assert cm.obstacle_names == ["ball"]
    world = cm.world_distances(q)
    assert min(w["distance"] for w in world) < 0 and {w["b"] for w in world} == {"ball"}
    assert any(c["b"] == "ball" for c in cm.collisions(q))
    cm.clear_obstacles()
    assert cm.world_distances(q) == []
    for call in (
        lambda: cm.add_obstacle("x", "torus", [1.0]),
        lambda: cm.add_obstacle("x", "box", [1.0]),
        lambda: cm.add_obstacle("x", "sphere", [1.0], np.diag([2.0, 1, 1, 1])),
        lambda: cm.distances(np.zeros(3)),
        lambda: kinetree.CollisionModel(model, srdf="no/such.srdf"),
        lambda: kinetree.CollisionModel(model, srdf="<robot><disable_collisions link1='nope' link2='panda_link1'/></robot>"),
    ):
        with pytest.raises(kinetree.CollisionError):
            call()
