"""Batches equal one-by-one calls bit for bit, the contract names exist, round trips, pickling,
threads, and the docstring examples."""

import doctest
import pickle
import threading

import numpy as np
import pytest

import kinetree
from conftest import PANDA

# name -> (inputs as a function of (model, q, v, a), kwargs)
PER_STATE = {
    "link_placements": lambda m, q, v, a: ((q,), {}),
    "frame_placements": lambda m, q, v, a: ((q,), {}),
    "frame_placement": lambda m, q, v, a: ((q, m.link_names[-1]), {}),
    "relative_transform": lambda m, q, v, a: ((q, m.link_names[1], m.link_names[-1]), {}),
    "frame_jacobian": lambda m, q, v, a: ((q, m.link_names[-1]), {"reference": "local"}),
    "frame_jacobian_time_variation": lambda m, q, v, a: ((q, v, m.link_names[-1]), {}),
    "frame_velocity": lambda m, q, v, a: ((q, v, m.link_names[-1]), {"reference": "world"}),
    "frame_acceleration": lambda m, q, v, a: ((q, v, a, m.link_names[-1]), {}),
    "rnea": lambda m, q, v, a: ((q, v, a), {}),
    "nle": lambda m, q, v, a: ((q, v), {}),
    "gravity": lambda m, q, v, a: ((q,), {}),
    "crba": lambda m, q, v, a: ((q,), {}),
    "aba": lambda m, q, v, a: ((q, v, a), {}),
    "minv": lambda m, q, v, a: ((q,), {}),
    "kinetic_energy": lambda m, q, v, a: ((q, v), {}),
    "potential_energy": lambda m, q, v, a: ((q,), {}),
    "com": lambda m, q, v, a: ((q,), {}),
    "com_jacobian": lambda m, q, v, a: ((q,), {}),
    "centroidal_momentum": lambda m, q, v, a: ((q, v), {}),
    "integrate": lambda m, q, v, a: ((q, v), {}),
    "difference": lambda m, q, v, a: ((q, m.integrate(q, v)), {}),
    "interpolate": lambda m, q, v, a: ((q, m.integrate(q, v), 0.3), {}),
    "normalize": lambda m, q, v, a: ((q,), {}),
}


def states(model, n, seed=0):
    rng = np.random.default_rng(seed)
    q = model.random_configuration(n, seed=seed)
    return q, rng.uniform(-1, 1, (n, model.nv)), rng.uniform(-1, 1, (n, model.nv))


@pytest.mark.parametrize("method", sorted(PER_STATE))
@pytest.mark.parametrize("robot", ["panda", "talos"])
def test_batch_equals_one_by_one_exactly(method, robot, request):
    model = request.getfixturevalue(robot)
    q, v, a = states(model, 64)
    args, kwargs = PER_STATE[method](model, q, v, a)
    stacked = getattr(model, method)(*args, **kwargs)
    assert stacked.shape[0] == 64
    for i in (0, 1, 17, 63):
        one_args = [x[i] if isinstance(x, np.ndarray) else x for x in args]
        one = np.asarray(getattr(model, method)(*one_args, **kwargs))
        assert stacked[i].shape == one.shape
        assert np.array_equal(stacked[i], one), method  # bit for bit, not approximately


def test_contract_names_and_shapes(panda):
    assert [(j.name, j.idx_q, j.nq, j.idx_v, j.nv) for j in panda.joints][:2] == [
        ("panda_joint1", 0, 1, 0, 1),
        ("panda_joint2", 1, 1, 1, 1),
    ]
    q = panda.random_configuration(5, seed=1)
    assert panda.link_placements(q[0]).shape == (len(panda.link_names), 4, 4)
    assert panda.link_placements(q).shape == (5, len(panda.link_names), 4, 4)
    assert panda.frame_jacobian(q[0], "panda_hand_tcp").shape == (6, panda.nv)
    assert panda.frame_jacobian(q, "panda_hand_tcp", reference="local_world_aligned").shape == (5, 6, 9)
    assert panda.crba(q).shape == (5, 9, 9)
    assert panda.rnea(q, np.zeros((5, 9)), np.zeros((5, 9))).shape == (5, 9)
    assert panda.aba(q[0], np.zeros(9), np.zeros(9)).shape == (9,)
    assert isinstance(panda.kinetic_energy(q[0], np.zeros(9)), float)
    assert panda.kinetic_energy(q, np.zeros((5, 9))).shape == (5,)
    # lists and integer arrays are accepted and converted
    assert np.array_equal(panda.gravity([0] * 9), panda.gravity(np.zeros(9)))
    # non-contiguous input
    wide = np.zeros((5, 18))
    wide[:, ::2] = q
    assert np.array_equal(panda.crba(wide[:, ::2]), panda.crba(q))
    # an empty stack
    assert panda.crba(np.zeros((0, 9))).shape == (0, 9, 9)


def test_rigid_body_dynamics_ignore_joint_damping():
    """rnea/aba are the rigid-body quantities even when the URDF declares damping and friction."""
    urdf = """<robot name="p"><link name="base"/>
      <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
        <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/>
        <axis xyz="0 1 0"/><dynamics damping="3.0" friction="1.0"/></joint></robot>"""
    m = kinetree.Model.from_urdf(urdf)
    # m·g·l about +y against gravity, plus m·l²·a; no damping (3·v) or friction term.
    np.testing.assert_allclose(m.rnea([0.0], [2.0], [2.0]), [-9.81 * 0.5 + 0.25 * 2.0], atol=1e-12)
    np.testing.assert_allclose(m.aba([0.0], [2.0], [0.0]), [9.81 * 0.5 / 0.25], atol=1e-12)


def test_configuration_round_trips(panda, talos):
    for model in (panda, talos):
        q0 = model.random_configuration(10, seed=3)
        q1 = model.random_configuration(10, seed=4)
        v = model.difference(q0, q1)
        back = model.integrate(q0, v)
        np.testing.assert_allclose(model.difference(back, q1), 0.0, atol=1e-9)
        np.testing.assert_allclose(model.difference(model.interpolate(q0, q1, 0.0), q0), 0.0, atol=1e-12)
        np.testing.assert_allclose(model.difference(model.interpolate(q0, q1, 1.0), q1), 0.0, atol=1e-9)
        d = model.dict_from_q(q0[0])
        assert set(d) == set(model.joint_names)
        np.testing.assert_array_equal(model.q_from_dict(d), q0[0])
        dv = model.dict_from_v(v[0])
        np.testing.assert_array_equal(model.v_from_dict(dv), v[0])
    assert talos.root_joint == "floating" and talos.joints[0].nq == 7
    np.testing.assert_array_equal(talos.normalize(talos.neutral()), talos.neutral())
    assert np.array_equal(panda.random_configuration(seed=5), panda.random_configuration(seed=5))


def test_model_text_round_trips(panda):
    q = panda.random_configuration(8, seed=2)
    for again in (
        kinetree.Model.from_urdf(panda.to_urdf()),
        kinetree.Model.from_json(panda.to_json()),
        kinetree.Model.from_urdf(PANDA),  # a pathlib.Path
    ):
        assert again.link_names == panda.link_names
        np.testing.assert_allclose(again.link_placements(q), panda.link_placements(q), atol=1e-12)
        np.testing.assert_allclose(again.crba(q), panda.crba(q), rtol=1e-12, atol=1e-12)


def test_dh_model_matches_the_textbook():
    """Standard DH planar two-link arm: the tip is at (l1 cos q1 + l2 cos(q1+q2), ...)."""
    arm = kinetree.Model.from_dh([[1.0, 0, 0, 0], [0.8, 0, 0, 0]])
    q = np.array([0.3, -0.7])
    tip = arm.frame_placement(q, "dh2")[:3, 3]
    np.testing.assert_allclose(tip, [np.cos(0.3) + 0.8 * np.cos(-0.4), np.sin(0.3) + 0.8 * np.sin(-0.4), 0], atol=1e-15)
    slider = kinetree.Model.from_dh([[0, 0, 0.1, 0]], kinds=["prismatic"])
    assert slider.frame_placement([0.25], "dh1")[2, 3] == pytest.approx(0.35)
    modified = kinetree.Model.from_dh([[0.0, 0, 0, 0], [1.0, 0, 0, 0]], modified=True)
    assert modified.frame_placement([0.0, 0.0], "dh2")[0, 3] == pytest.approx(1.0)


def test_pickle_rebuilds_the_same_model(panda, talos):
    for model in (panda, talos, kinetree.Model.from_dh([[1.0, 0.2, 0.1, 0.3]])):
        again = pickle.loads(pickle.dumps(model))
        assert again.link_names == model.link_names and again.nq == model.nq
        q = model.random_configuration(4, seed=1)
        v = np.ones((4, model.nv))
        assert np.array_equal(again.link_placements(q), model.link_placements(q))
        assert np.array_equal(again.rnea(q, v, v), model.rnea(q, v, v))


def test_threads_share_a_model(panda):
    """Eight threads calling one model (one-state calls and batches) get the sequential results."""
    q = panda.random_configuration(200, seed=8)
    v = np.ones((200, 9))
    expected_m = panda.crba(q)
    expected_tau = [panda.rnea(q[i], v[i], v[i]) for i in range(200)]
    failures = []

    def work(k):
        for i in range(k, 200, 8):
            if not np.array_equal(panda.rnea(q[i], v[i], v[i]), expected_tau[i]):
                failures.append(i)
        if not np.array_equal(panda.crba(q), expected_m):
            failures.append(-k)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert failures == []


def test_simulate_conserves_energy(panda):
    q0 = panda.q_from_dict({"panda_joint2": 0.5, "panda_joint4": -1.5})
    qs, vs = panda.simulate(q0, np.zeros(9), dt=1e-3, steps=300)
    assert qs.shape == (301, 9) and vs.shape == (301, 9)
    e = panda.kinetic_energy(qs, vs) + panda.potential_energy(qs)
    assert np.ptp(e) < 1e-6 * max(1.0, abs(e[0]))
    assert np.abs(vs[-1]).max() > 0.1  # it fell
    # a held torque keeps it still
    qs, vs = panda.simulate(q0, np.zeros(9), tau=panda.gravity(q0), steps=50, integrator="euler")
    np.testing.assert_allclose(qs[-1], q0, atol=1e-9)


def docstrings():
    """(name, docstring) of the package, its classes and their members."""
    yield "kinetree", kinetree.__doc__
    for name in kinetree.__all__:
        obj = getattr(kinetree, name)
        if isinstance(obj, type):
            yield name, obj.__doc__
            for member, value in vars(obj).items():
                if not member.startswith("__"):
                    yield f"{name}.{member}", getattr(value, "__doc__", None)


def test_docstring_examples_run(panda):
    parser, runner = doctest.DocTestParser(), doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    ran = 0
    for name, doc in docstrings():
        if not doc or ">>>" not in doc:
            continue
        globs = {"kinetree": kinetree, "np": np, "panda": panda}
        test = parser.get_doctest(doc, globs, name, None, 0)
        runner.run(test)
        ran += len(test.examples)
    result = runner.summarize(verbose=False)
    assert result.failed == 0
    assert ran >= 40, ran


def test_a_composite_joint_is_one_joint():
    """trip_kinematics' Transformation as a JSON composite joint: one entry in ``joints``."""
    leg = kinetree.Model.from_json("""{"links": [{"name": "pelvis"}, {"name": "thigh",
        "inertial": {"mass": 1.0, "inertia": {"ixx": 0.01, "iyy": 0.01, "izz": 0.01}}}],
      "joints": [{"name": "hip", "type": "composite", "parent": "pelvis", "child": "thigh",
        "factors": [{"param": "tx", "value": 0.1}, {"param": "ry"}, {"param": "rz"}]}]}""")
    [hip] = leg.joints
    assert (hip.name, hip.kind, hip.idx_q, hip.nq, hip.idx_v, hip.nv) == ("hip", "composite", 0, 2, 0, 2)
    assert (hip.parent_link, hip.child_link) == ("pelvis", "thigh")
    assert leg.joint_names == ["hip"]
    q = leg.q_from_dict({"hip": [0.3, -0.2]})
    np.testing.assert_array_equal(q, [0.3, -0.2])
    np.testing.assert_array_equal(leg.dict_from_q(q)["hip"], [0.3, -0.2])
    # Ry(0.3)·Rz(-0.2) after the constant tx = 0.1.
    pose = leg.frame_placement(q, "thigh")
    np.testing.assert_allclose(pose[:3, 3], [0.1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(pose[2, 0], -np.sin(0.3) * np.cos(-0.2), atol=1e-15)


LEG = """{"links": [{"name": "pelvis"}, {"name": "thigh",
    "inertial": {"mass": 1.0, "inertia": {"ixx": 0.01, "iyy": 0.01, "izz": 0.01}}},
    {"name": "shin", "inertial": {"mass": 0.5, "inertia": {"ixx": 0.01, "iyy": 0.01, "izz": 0.01}}}],
  "joints": [{"name": "hip", "type": "composite", "parent": "pelvis", "child": "thigh",
    "factors": [{"param": "tx", "value": 0.1}, {"param": "ry"}, {"param": "rz"}, {"param": "tz", "value": -0.2}]},
    {"name": "knee", "type": "revolute", "parent": "thigh", "child": "shin", "axis": [0, 1, 0],
     "origin": {"xyz": [0, 0, -0.4]}, "limits": {"lower": -2, "upper": 2, "effort": 10, "velocity": 5}}]}"""


def test_link_lists_leave_out_a_composite_joints_virtual_links():
    """The URDF/JSON author's links only: ``link_names``, ``nlinks`` and ``link_placements`` (one
    state, stacks run inline and in parallel, ``out=``) skip the massless links a composite joint
    is expanded with, and each pose is that link's ``frame_placement``."""
    leg = kinetree.Model.from_json(LEG)
    assert leg.link_names == ["pelvis", "thigh", "shin"]
    assert leg.nlinks == 3
    assert "3 links" in repr(leg)
    assert leg.joint_names == ["hip", "knee"]
    q = leg.q_from_dict({"hip": [0.3, -0.2], "knee": 0.7})
    poses = leg.link_placements(q)
    assert poses.shape == (3, 4, 4)
    for name, pose in zip(leg.link_names, poses):
        assert np.array_equal(pose, leg.frame_placement(q, name)), name
    # the thigh hangs at tx = 0.1 then Ry(0.3) Rz(-0.2), then tz = -0.2 along the rotated z
    rotation = poses[1, :3, :3]
    np.testing.assert_allclose(poses[1, :3, 3], [0.1, 0, 0] + rotation @ [0, 0, -0.2], atol=1e-15)
    for n in (3, 64):
        Q = leg.random_configuration(n, seed=n)
        stacked = leg.link_placements(Q)
        assert stacked.shape == (n, 3, 4, 4)
        for i in range(n):
            assert np.array_equal(stacked[i], leg.link_placements(Q[i])), (n, i)
        out = np.full((n, 3, 4, 4), np.nan)
        assert leg.link_placements(Q, out=out) is out
        assert np.array_equal(out, stacked)
    out = np.full((3, 4, 4), np.nan)
    assert leg.link_placements(q, out=out) is out
    assert np.array_equal(out, poses)
    with pytest.raises(kinetree.KinematicsError, match=r"shape \(3, 4, 4\)"):
        leg.link_placements(q, out=np.zeros((5, 4, 4)))


def test_frame_names_are_found_whatever_string_object_carries_them(panda):
    # frame_jacobian and frame_placement cache names by string object: equal strings made at run
    # time, more names than the cache holds, and unknown names all behave as the first call.
    q = panda.random_configuration(seed=3)
    names = panda.link_names + panda.frame_names
    assert len(names) > 8
    expected = {n: (panda.frame_jacobian(q, n), panda.frame_placement(q, n)) for n in names}
    for _ in range(2):
        for n in names:
            fresh = "".join(list(n))  # an equal string, another object
            for s in (n, fresh):
                assert np.array_equal(panda.frame_jacobian(q, s), expected[n][0])
                assert np.array_equal(panda.frame_placement(q, s), expected[n][1])
    tcp = "panda_hand_tcp"
    for ref in ("local", "world", "local_world_aligned"):
        fresh = "".join(list(ref))
        assert np.array_equal(panda.frame_jacobian(q, tcp, fresh), panda.frame_jacobian(q, tcp, ref))
        assert np.array_equal(panda.frame_jacobian(q, tcp, reference=ref),
                              panda.frame_jacobian(q, tcp, ref))
    assert not np.array_equal(panda.frame_jacobian(q, tcp, "local"), panda.frame_jacobian(q, tcp, "world"))
    for _ in range(2):  # an unknown name is not cached as known
        with pytest.raises(kinetree.KinematicsError, match="no_such_link"):
            panda.frame_jacobian(q, "no_such_link")
    with pytest.raises(kinetree.KinematicsError, match="reference must be"):
        panda.frame_jacobian(q, tcp, "".join(list("sideways")))


def test_reference_none_is_local_world_aligned_and_names_are_found_by_any_string(panda):
    q = panda.random_configuration(seed=5)
    v = np.random.default_rng(5).uniform(-1, 1, panda.nv)
    a = np.random.default_rng(6).uniform(-1, 1, panda.nv)
    tcp = "panda_hand_tcp"
    calls = {
        "frame_jacobian": (q, tcp),
        "frame_jacobian_time_variation": (q, v, tcp),
        "frame_velocity": (q, v, tcp),
        "frame_acceleration": (q, v, a, tcp),
    }
    for method, args in calls.items():
        fn = getattr(panda, method)
        lwa = fn(*args, "local_world_aligned")
        assert np.array_equal(fn(*args), lwa), method
        assert np.array_equal(fn(*args, None), lwa), method
        assert np.array_equal(fn(*args, reference=None), lwa), method
        assert not np.array_equal(fn(*args, "local"), lwa) or not lwa.any(), method
        # an equal name in another string object, twice (the second time from the cache)
        for _ in range(2):
            fresh = (*args[:-1], "".join(list(tcp)))
            assert np.array_equal(fn(*fresh, "".join(list("world"))), fn(*args, "world")), method
        with pytest.raises(kinetree.KinematicsError, match="reference must be"):
            fn(*args, "sideways")
        with pytest.raises(TypeError):
            fn(*args, 3)
    expected = panda.relative_transform(q, "panda_link0", tcp)
    for _ in range(2):
        got = panda.relative_transform(q, "".join(list("panda_link0")), "".join(list(tcp)))
        assert np.array_equal(got, expected)
    np.testing.assert_allclose(expected, panda.frame_placement(q, tcp), atol=1e-15)
