"""Every public callable against a generated catalogue of hostile inputs (issue #11).

Each callable has one valid call (the baseline, which must succeed); the catalogue replaces
one argument at a time by each hostile value (wrong shapes and dtypes, NaN, inf, 1e308,
subnormals, bad names, bad files, huge sizes). The outcome must be a result without NaN, or a
kinetree exception, ValueError or TypeError; not OverflowError (an int out of an argument's
range is a kinetree error naming the argument). Never a crash, a hang, or a Rust panic (pyo3's
PanicException is a BaseException, so it is not caught as an Exception and fails the test).
"""

import math

import numpy as np
import pytest

import kinetree

from conftest import ROOT

NAN, INF = float("nan"), float("inf")
ROBOTS = ROOT / "tests" / "data" / "robots"
ACCEPTED = (kinetree.KinetreeError, ValueError, TypeError)


def hostile_values(n):
    """Hostile stand-ins for any argument; `n` is the length a state vector should have."""
    return [
        # Wrong kinds of thing.
        None, True, 0, -1, 2**64, 10**30, 1e308, -1e308, NAN, INF, -INF, 5e-324, "", "nope",
        "\0", "x" * 10_000, b"bytes", object(), {"a": 1}, [], [[]], [1.0, [2.0]],
        # Arrays of the wrong shape, dtype or content.
        np.zeros(0), np.zeros(n - 1), np.zeros(n + 1), np.zeros((2, 3, n)), np.zeros((0, n)),
        np.zeros((1, 0)), np.full(n, NAN), np.full(n, INF), np.full(n, 1e308), np.full(n, -1e308),
        np.full(n, 5e-324), np.zeros(n, dtype=np.complex128), np.zeros(n, dtype=np.int8),
        np.array(["a"] * n), np.zeros(n, dtype=object), np.zeros((n, n)), np.full((4, 4), NAN),
        np.full((4, 4), 1e308), np.zeros((4, 4)), np.zeros(n)[::2],
        # Complex numbers (numpy would drop the imaginary parts with only a warning).
        np.full(n, 0.1 + 1j), np.full(3, 0.1 + 1j), np.full((4, 4), 1j),
        np.complex128(0.5 + 1j), np.complex64(0.5 + 1j), np.complex128(0.5),
        # Files that are not model files.
        str(ROBOTS), "/dev/null", "no/such/file.urdf", str(ROBOTS / "panda_srdf" / "missing.srdf"),
    ]


def assert_no_nan(result, where):
    """No NaN anywhere in a result (arrays, floats, containers, reports)."""
    if isinstance(result, np.ndarray):
        if result.dtype.kind in "fc":
            assert not np.isnan(result).any(), where
    elif isinstance(result, float):
        assert not math.isnan(result), where
    elif isinstance(result, (list, tuple)):
        for x in result:
            assert_no_nan(x, where)
    elif isinstance(result, dict):
        for k, x in result.items():
            assert_no_nan(k, where)
            assert_no_nan(x, where)
    elif isinstance(result, kinetree.IkReport):
        for name in ("position_error", "orientation_error", "elapsed", "residual"):
            assert_no_nan(getattr(result, name), f"{where}.{name}")


def call_and_check(fn, args, kwargs, where):
    try:
        result = fn(*args, **kwargs)
    except ACCEPTED:
        return False
    assert_no_nan(result, where)
    return True


@pytest.fixture(scope="module")
def setup():
    """The objects whose methods are called, each built by a valid call."""
    model = kinetree.Model.from_urdf(str(ROBOTS / "panda.urdf"))
    ws = model.sample_workspace("panda_hand_tcp", samples=200, seed=1)
    vox = ws.voxelize(0.1)
    ik = kinetree.IkSolver(model, time_budget=None, max_iterations=200, seed=0)
    cm = kinetree.CollisionModel(model, mesh_paths=[str(ROBOTS)])
    return model, ws, vox, ik, cm


def baselines(model, ws, vox, ik, cm):
    """(name, callable, valid positional args, valid keyword args) for every public callable."""
    q, z = model.neutral(), np.zeros(model.nv)
    q2 = model.random_configuration(2, seed=0)
    goal = np.eye(4)
    goal[:3, 3] = [0.4, 0.0, 0.5]
    urdf = (ROBOTS / "panda.urdf").read_text()
    json_text = model.to_json()
    M = kinetree.Model
    return [
        ("Model.from_urdf", M.from_urdf, [urdf], {"floating": False}),
        ("Model.from_json", M.from_json, [json_text], {"floating": None}),
        ("Model.from_mjcf", M.from_mjcf,
         ['<mujoco><worldbody><body><joint/><geom size="0.1"/></body></worldbody></mujoco>'], {}),
        ("Model.from_sdf", M.from_sdf,
         ['<sdf version="1.7"><model name="m"><link name="a"/></model></sdf>'], {}),
        ("Model.load", M.load, [str(ROBOTS / "panda.urdf")], {"floating": None}),
        ("Model.q_from_mujoco", model.q_from_mujoco, [q], {}),
        ("Model.q_to_mujoco", model.q_to_mujoco, [q2], {}),
        ("Model.v_from_mujoco", model.v_from_mujoco, [q, z], {}),
        ("Model.v_to_mujoco", model.v_to_mujoco, [q, z], {}),
        ("Model.a_from_mujoco", model.a_from_mujoco, [q, z, z], {}),
        ("Model.a_to_mujoco", model.a_to_mujoco, [q, z, z], {}),
        ("Model.tau_from_mujoco", model.tau_from_mujoco, [q, z], {}),
        ("Model.tau_to_mujoco", model.tau_to_mujoco, [q, z], {}),
        ("Model.from_dh", M.from_dh, [[[0.3, 0.0, 0.0, 0.0], [0.0, 0.2, 0.0, 1.0]]],
         {"modified": False, "kinds": ["revolute", "revolute"], "name": "dh"}),
        ("Model.to_urdf", model.to_urdf, [], {}),
        ("Model.to_json", model.to_json, [], {}),
        ("Model.neutral", model.neutral, [], {}),
        ("Model.random_configuration", model.random_configuration, [], {"n": 3, "seed": 1}),
        ("Model.integrate", model.integrate, [q, z], {}),
        ("Model.difference", model.difference, [q, q], {}),
        ("Model.interpolate", model.interpolate, [q, q, 0.5], {}),
        ("Model.normalize", model.normalize, [q], {}),
        ("Model.q_from_dict", model.q_from_dict, [{"panda_joint1": 0.1}], {"base": q}),
        ("Model.v_from_dict", model.v_from_dict, [{"panda_joint1": 0.1}], {}),
        ("Model.dict_from_q", model.dict_from_q, [q], {}),
        ("Model.dict_from_v", model.dict_from_v, [z], {}),
        ("Model.link_placements", model.link_placements, [q2], {}),
        ("Model.frame_placements", model.frame_placements, [q], {}),
        ("Model.frame_placement", model.frame_placement, [q, "panda_hand"], {}),
        ("Model.relative_transform", model.relative_transform, [q, "panda_link0", "panda_hand"], {}),
        ("Model.frame_jacobian", model.frame_jacobian, [q, "panda_hand"], {"reference": "world"}),
        ("Model.frame_jacobian_time_variation", model.frame_jacobian_time_variation,
         [q, z, "panda_hand"], {"reference": "local"}),
        ("Model.frame_velocity", model.frame_velocity, [q, z, "panda_hand"], {}),
        ("Model.frame_acceleration", model.frame_acceleration, [q, z, z, "panda_hand"], {}),
        ("Model.rnea", model.rnea, [q2, np.zeros((2, 9)), np.zeros((2, 9))], {}),
        ("Model.nle", model.nle, [q, z], {}),
        ("Model.gravity", model.gravity, [q], {}),
        ("Model.crba", model.crba, [q], {}),
        ("Model.aba", model.aba, [q, z, z], {}),
        ("Model.minv", model.minv, [q], {}),
        ("Model.rnea_derivatives", model.rnea_derivatives, [q, z, z], {}),
        ("Model.gravity_derivatives", model.gravity_derivatives, [q], {}),
        ("Model.aba_derivatives", model.aba_derivatives, [q, z, z], {}),
        ("Model.kinetic_energy", model.kinetic_energy, [q, z], {}),
        ("Model.potential_energy", model.potential_energy, [q], {}),
        ("Model.com", model.com, [q], {}),
        ("Model.com_jacobian", model.com_jacobian, [q], {}),
        ("Model.centroidal_momentum", model.centroidal_momentum, [q, z], {}),
        ("Model.simulate", model.simulate, [q, z],
         {"tau": z, "dt": 1e-3, "steps": 5, "integrator": "euler"}),
        ("Model.sample_workspace", model.sample_workspace, ["panda_hand"],
         {"samples": 50, "seed": 0, "grid": None, "task": "position", "q0": None}),
        ("ReachableSet.bounds", ws.bounds, [], {}),
        ("ReachableSet.max_reach", ws.max_reach, [[0.0, 0.0, 0.333]], {}),
        ("ReachableSet.voxelize", ws.voxelize, [0.1], {}),
        ("VoxelMap.is_reachable", vox.is_reachable, [[0.3, 0.0, 0.5]], {}),
        ("VoxelMap.voxels", vox.voxels, [], {}),
        ("VoxelMap.merge", vox.merge, [vox], {}),
        ("IkSolver", kinetree.IkSolver, [model],
         {"position_tolerance": 1e-4, "max_iterations": 100, "time_budget": None, "seed": 0,
          "damping": 0.1, "orientation_weight": 0.35, "max_targets": 4}),
        ("IkSolver.set_moving_joints", ik.set_moving_joints, [["panda_joint1", "panda_joint2"]], {}),
        ("IkSolver.set_posture", ik.set_posture, [q], {"gain": 0.1}),
        ("IkSolver.solve", ik.solve, ["panda_hand", goal], {"q0": q, "weights": None}),
        ("IkSolver.solve_targets", ik.solve_targets, [[("panda_hand", goal)]], {"q0": q}),
        ("IkSolver.solve_batch", ik.solve_batch, ["panda_hand", np.array([goal, goal])], {"q0": None}),
        ("CollisionModel", kinetree.CollisionModel, [model],
         {"mesh_paths": [str(ROBOTS)], "srdf": None, "convex": False, "skip_missing_meshes": False}),
        ("CollisionModel.add_obstacle", cm.add_obstacle, ["box", "box", [0.1, 0.1, 0.1]],
         {"pose": np.eye(4)}),
        ("CollisionModel.clear_obstacles", cm.clear_obstacles, [], {}),
        ("CollisionModel.any_collision", cm.any_collision, [q], {}),
        ("CollisionModel.collisions", cm.collisions, [q], {}),
        ("CollisionModel.distances", cm.distances, [q], {}),
        ("CollisionModel.world_distances", cm.world_distances, [q], {}),
        ("CollisionModel.link_pair_distances", cm.link_pair_distances, [q], {}),
        ("CollisionModel.set_distance_tolerance", cm.set_distance_tolerance, [1e-8], {}),
    ]


def public_callables():
    """The public callables kinetree exposes: module functions, constructors and methods."""
    names = set()
    for name in kinetree.__all__:
        obj = getattr(kinetree, name)
        if not callable(obj) or (isinstance(obj, type) and issubclass(obj, BaseException)):
            continue
        if isinstance(obj, type):
            if "__init__" in vars(obj) or "__new__" in vars(obj):
                names.add(name)
            for attr, member in vars(obj).items():
                if not attr.startswith("_") and callable(member):
                    names.add(f"{name}.{attr}")
        else:
            names.add(name)
    return names


def test_the_catalogue_covers_every_public_callable(setup):
    covered = {name for name, *_ in baselines(*setup)}
    missing = public_callables() - covered - {"Joint", "IkReport", "ReachableSet", "VoxelMap", "Model"}
    assert not missing, f"add a baseline for {sorted(missing)}"


# A complex argument converted with its imaginary part dropped is a silent wrong answer.
@pytest.mark.filterwarnings("error::numpy.exceptions.ComplexWarning")
def test_hostile_arguments_raise_or_give_finite_results(setup):
    model = setup[0]
    values = hostile_values(model.nq)
    calls = outcomes = 0
    for name, fn, args, kwargs in baselines(*setup):
        # The baseline itself succeeds, so every refusal below is caused by the hostile value.
        assert call_and_check(fn, args, kwargs, name), f"the baseline of {name} fails"
        for k in range(len(args)):
            for bad in values:
                hostile = list(args)
                hostile[k] = bad
                outcomes += call_and_check(fn, hostile, kwargs, f"{name} arg {k} = {bad!r:.60}")
                calls += 1
        for key in kwargs:
            for bad in values:
                outcomes += call_and_check(
                    fn, args, {**kwargs, key: bad}, f"{name} {key} = {bad!r:.60}"
                )
                calls += 1
    # Most hostile calls are refused; a few are legitimately answered (0 for an int, a
    # stacked empty batch), and those answers were checked above.
    assert calls > 3000 and outcomes < calls, (calls, outcomes)


def test_huge_sizes_are_refused_not_attempted(setup):
    model, ws, _, ik, _ = setup
    for fn, args, kwargs in [
        (model.random_configuration, [], {"n": 10**15}),
        (model.sample_workspace, ["panda_hand"], {"samples": 10**15}),
        (model.sample_workspace, ["panda_hand"], {"grid": 10**6}),
        (ws.voxelize, [1e-300], {}),
    ]:
        with pytest.raises(ACCEPTED):
            fn(*args, **kwargs)
    # Allocations that would abort the interpreter are refused with the reason. A broadcast
    # view of 10**9 states is small; its copy or the stacked result would not be.
    many = np.broadcast_to(model.neutral(), (10**9, model.nq))
    for fn, args, kwargs in [
        (model.simulate, [model.neutral(), np.zeros(model.nv)], {"steps": 10**15}),
        (model.link_placements, [many], {}),
        (model.frame_jacobian, [many, "panda_hand"], {}),
        (ik.solve_batch, ["panda_hand", np.broadcast_to(np.eye(4), (10**9, 4, 4))], {}),
    ]:
        with pytest.raises(ValueError, match="do not fit in memory"):
            fn(*args, **kwargs)
    # Sizes past a documented limit are refused by name before anything is allocated.
    with pytest.raises(kinetree.IkError, match="max_targets = 1000000000 exceeds the limit of 256"):
        kinetree.IkSolver(model, max_targets=10**9)
    assert kinetree.IkSolver(model, max_targets=256) is not None
    with pytest.raises(kinetree.ModelError, match="100000000 DH rows, more than the 10000 accepted"):
        kinetree.Model.from_dh(np.broadcast_to(np.array([0.1, 0.0, 0.0, 0.0]), (10**8, 4)))
    assert kinetree.Model.from_dh(np.full((10_000, 4), 0.01)).nq == 10_000



def test_counts_out_of_range_are_kinetree_errors_naming_the_argument(setup):
    """-1 or 2**64 for a count or a seed raised OverflowError, not a kinetree error."""
    model = setup[0]
    q, z = model.neutral(), np.zeros(model.nv)
    cases = [
        (model.random_configuration, [-1], {}, "n", kinetree.KinematicsError),
        (model.random_configuration, [], {"seed": -1}, "seed", kinetree.KinematicsError),
        (model.random_configuration, [], {"seed": 2**64}, "seed", kinetree.KinematicsError),
        (model.simulate, [q, z], {"steps": -1}, "steps", kinetree.DynamicsError),
        (model.sample_workspace, ["panda_hand"], {"samples": -5}, "samples", kinetree.KinetreeError),
        (model.sample_workspace, ["panda_hand"], {"grid": 10**30}, "grid", kinetree.KinetreeError),
        (model.sample_workspace, ["panda_hand"], {"seed": -1}, "seed", kinetree.KinetreeError),
        (kinetree.IkSolver, [model], {"max_targets": -1}, "max_targets", kinetree.IkError),
        (kinetree.IkSolver, [model], {"max_iterations": -3}, "max_iterations", kinetree.IkError),
        (kinetree.IkSolver, [model], {"max_iterations_per_try": -3}, "max_iterations_per_try", kinetree.IkError),
        (kinetree.IkSolver, [model], {"max_restarts": -1}, "max_restarts", kinetree.IkError),
        (kinetree.IkSolver, [model], {"seed": -(2**70)}, "seed", kinetree.IkError),
    ]
    for fn, args, kwargs, name, error in cases:
        with pytest.raises(error, match=rf"^{name} must be a whole number from 0 to 18446744073709551615, got -?\d+$"):
            fn(*args, **kwargs)
    # Still a TypeError naming the argument for what is not an int; the largest seed is valid.
    with pytest.raises(TypeError, match="seed"):
        model.random_configuration(seed=1.5)
    assert model.random_configuration(seed=2**64 - 1).shape == (model.nq,)
