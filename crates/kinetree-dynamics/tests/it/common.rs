//! Shared helpers: the reference robots, their named states, random states and a model with one
//! joint of every kind.

use kinetree_dynamics::kinematics::batch::Simd;
use kinetree_dynamics::kinematics::configuration::random_configuration;
use kinetree_dynamics::model::spatial::glam::DVec3;
use kinetree_dynamics::model::spatial::{Se3, Symmetric3};
use kinetree_dynamics::model::{
    JointDynamics, JointKind, JointSpec, Link, Model, ModelBuilder, RootJoint,
};
pub(crate) use kinetree_test_support::{q_of, reference_dir, robots, v_of, values};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use serde_json::Value;

/// The reference robots' models plus [`every_kind`], for the identity tests.
pub(crate) fn all_models() -> Vec<(String, Model)> {
    let mut out: Vec<(String, Model)> = robots().into_iter().map(|(n, _, m)| (n, m)).collect();
    out.push(("every_kind".into(), every_kind(RootJoint::Fixed)));
    out.push((
        "every_kind_floating".into(),
        every_kind(RootJoint::Floating),
    ));
    out
}

/// Our index for each index of Pinocchio's v order, per the reference joint table.
pub(crate) fn index_map(model: &Model, reference: &Value) -> Vec<usize> {
    let mut map = vec![usize::MAX; model.nv()];
    for j in reference["joints"].as_array().unwrap() {
        let ours = model.joint_v_range(model.joint_index(j["name"].as_str().unwrap()).unwrap());
        let theirs = j["idx_v"].as_u64().unwrap() as usize;
        for (k, o) in ours.enumerate() {
            map[theirs + k] = o;
        }
    }
    assert!(map.iter().all(|&m| m < model.nv()));
    map
}

/// A random state: in-limit configuration, velocities and accelerations in [-1, 1].
pub(crate) fn random_state(model: &Model, rng: &mut SmallRng) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q = vec![0.0; model.nq()];
    random_configuration(model, rng, &mut q).unwrap();
    let mut uniform = || -> Vec<f64> {
        (0..model.nv())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect()
    };
    let v = uniform();
    let a = uniform();
    (q, v, a)
}

/// `n` random states of `model`, stacked: q (`n·nq`), v, a (`n·nv`); every third one is far
/// from the origin of the joint space (velocities and accelerations scaled by 7).
pub(crate) fn stacked_states(model: &Model, n: usize, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut r = rng(seed);
    let (mut qs, mut vs, mut as_) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        let (q, v, a) = random_state(model, &mut r);
        let scale = if k % 3 == 0 { 7.0 } else { 1.0 };
        qs.extend(q);
        vs.extend(v.iter().map(|x| x * scale));
        as_.extend(a.iter().map(|x| x * scale));
    }
    (qs, vs, as_)
}

pub(crate) fn rng(seed: u64) -> SmallRng {
    SmallRng::seed_from_u64(seed)
}

fn link(name: &str, mass: f64, com: [f64; 3], i: [f64; 3]) -> Link {
    Link::new(name).with_mass(
        mass,
        DVec3::from_array(com),
        Symmetric3::new(i[0], 0.01 * i[0], -0.02 * i[1], i[1], 0.015 * i[2], i[2]),
    )
}

/// A tree with one joint of every kind (off-axis axes, a fixed joint, two branches) and joint
/// damping, friction and armature on some joints.
pub(crate) fn every_kind(root: RootJoint) -> Model {
    every_kind_with_gravity(root, DVec3::new(0.0, 0.0, -9.81))
}

/// [`every_kind`] under the given gravity.
pub(crate) fn every_kind_with_gravity(root: RootJoint, gravity: DVec3) -> Model {
    let mut b = ModelBuilder::new("every_kind");
    b.root_joint(root);
    b.gravity(gravity);
    b.add_link(link("base", 2.0, [0.05, -0.02, 0.1], [0.05, 0.06, 0.07]));
    let place = |x: [f64; 3], r: [f64; 3]| Se3::from_xyz_rpy(x, r);
    let parts: [(&str, JointKind, &str, &str, Se3, DVec3, JointDynamics); 9] = [
        (
            "revolute",
            JointKind::Revolute,
            "base",
            "l1",
            place([0.1, 0.0, 0.2], [0.1, 0.2, 0.3]),
            DVec3::new(0.3, -0.5, 0.8),
            JointDynamics {
                damping: 0.3,
                friction: 0.2,
                armature: 0.05,
            },
        ),
        (
            "prismatic",
            JointKind::Prismatic,
            "l1",
            "l2",
            place([0.0, 0.3, 0.0], [0.0, 0.0, 0.5]),
            DVec3::Y,
            JointDynamics {
                damping: 1.0,
                friction: 0.0,
                armature: 0.1,
            },
        ),
        (
            "spherical",
            JointKind::Spherical,
            "l2",
            "l3",
            place([0.2, 0.0, 0.1], [0.3, -0.2, 0.1]),
            DVec3::Z,
            JointDynamics::default(),
        ),
        (
            "weld",
            JointKind::Fixed,
            "l3",
            "l4",
            place([0.0, 0.1, 0.25], [0.5, 0.0, 0.0]),
            DVec3::Z,
            JointDynamics::default(),
        ),
        (
            "cylindrical",
            JointKind::Cylindrical,
            "l4",
            "l5",
            place([0.1, 0.1, 0.0], [0.0, 0.4, 0.0]),
            DVec3::new(1.0, 1.0, 0.0),
            JointDynamics {
                damping: 0.1,
                friction: 0.05,
                armature: 0.0,
            },
        ),
        (
            "planar",
            JointKind::Planar,
            "l5",
            "l6",
            place([0.0, 0.0, 0.3], [0.0, 0.0, 0.0]),
            DVec3::new(0.0, 0.6, 0.8),
            JointDynamics::default(),
        ),
        (
            "continuous",
            JointKind::Continuous,
            "base",
            "m1",
            place([-0.2, 0.0, 0.1], [0.0, 0.0, 1.0]),
            DVec3::X,
            JointDynamics {
                damping: 0.0,
                friction: 0.0,
                armature: 0.2,
            },
        ),
        (
            "prismatic_z",
            JointKind::Prismatic,
            "m1",
            "m2",
            place([0.0, 0.0, -0.2], [0.0, 0.0, 0.0]),
            DVec3::Z,
            JointDynamics::default(),
        ),
        (
            "revolute_y",
            JointKind::Revolute,
            "m1",
            "m3",
            place([0.0, 0.2, 0.0], [0.2, 0.0, 0.0]),
            DVec3::Y,
            JointDynamics::default(),
        ),
    ];
    for (k, (name, kind, parent, child, placement, axis, dynamics)) in parts.into_iter().enumerate()
    {
        let s = 1.0 + 0.1 * k as f64;
        b.add_link(link(
            child,
            0.5 * s,
            [0.02 * s, 0.05, -0.03 * s],
            [0.004 * s, 0.005, 0.006 * s],
        ));
        b.add_joint(
            JointSpec::new(name, kind, parent, child)
                .with_placement(placement)
                .with_axis(axis)
                .with_dynamics(dynamics),
        );
    }
    b.build().unwrap()
}

/// `max |x - y| / max(max |y|, floor)`.
pub(crate) fn relative_error(x: &[f64], y: &[f64], floor: f64) -> f64 {
    assert_eq!(x.len(), y.len());
    let scale = y.iter().fold(floor, |m, v| m.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
        / scale
}

/// Row-major product of an `n x n` matrix with a vector.
pub(crate) fn mat_vec(m: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| (0..n).map(|j| m[i * n + j] * x[j]).sum())
        .collect()
}

/// Every instruction set of the batched kernels (those this CPU lacks fall back to one it has).
pub(crate) const SIMD: [Simd; 3] = [Simd::Portable, Simd::Avx2, Simd::Avx512];

/// Batch sizes: one state, lane widths and their neighbours, and a size no lane width divides.
pub(crate) const SIZES: [usize; 5] = [1, 4, 8, 9, 19];

/// Asserts `got` equals `want` bit for bit: the lane kernels repeat the one-state arithmetic in
/// the same order.
pub(crate) fn assert_bits(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.to_bits() == w.to_bits(),
            "{what}[{i}]: batched {g:e}, one-state {w:e}"
        );
    }
}

/// Asserts the three stacked `nv x nv` matrices `got` (named `names`) of the stacked states
/// `(q, v, x)` equal, state by state and bit for bit, the three that `one` computes for one
/// state `(q, v, x)`.
pub(crate) fn assert_matrices_per_state(
    model: &Model,
    (q, v, x): (&[f64], &[f64], &[f64]),
    got: [&[f64]; 3],
    names: [&str; 3],
    what: &str,
    mut one: impl FnMut(&[f64], &[f64], &[f64]) -> [Vec<f64>; 3],
) {
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    for k in 0..q.len() / nq {
        let r = k * nv..(k + 1) * nv;
        let want = one(&q[k * nq..(k + 1) * nq], &v[r.clone()], &x[r]);
        let m = k * nn..(k + 1) * nn;
        for ((got, want), name) in got.iter().zip(&want).zip(names) {
            assert_bits(&got[m.clone()], want, &format!("{what} state {k} {name}"));
        }
    }
}
