//! Strategies for random spatial values, 6x6 matrix helpers and comparisons shared by the tests.

use kinetree_spatial::{DMat3, DVec3, Force, Inertia, Motion, Se3, Symmetric3, rotation};
use proptest::prelude::*;
use std::f64::consts::PI;

/// Cases per property: enough to find a wrong sign, bounded for CI's two cores.
pub(crate) const CASES: u32 = 256;

pub(crate) fn config() -> ProptestConfig {
    ProptestConfig::with_cases(CASES)
}

/// A 6x6 matrix in row-major nested arrays, as `to_action_matrix` returns it.
pub(crate) type Mat6 = [[f64; 6]; 6];

pub(crate) fn mat6_vec(m: &Mat6, v: [f64; 6]) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (o, row) in out.iter_mut().zip(m) {
        *o = row.iter().zip(v).map(|(a, b)| a * b).sum();
    }
    out
}

pub(crate) fn mat6_mul(a: &Mat6, b: &Mat6) -> Mat6 {
    let mut out = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            out[i][j] = (0..6).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

pub(crate) fn transpose6(m: &Mat6) -> Mat6 {
    let mut out = [[0.0; 6]; 6];
    for (i, row) in m.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            out[j][i] = *x;
        }
    }
    out
}

pub(crate) const IDENTITY6: Mat6 = {
    let mut m = [[0.0; 6]; 6];
    let mut i = 0;
    while i < 6 {
        m[i][i] = 1.0;
        i += 1;
    }
    m
};

/// The largest absolute difference between two equally long lists of numbers.
pub(crate) fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

pub(crate) fn flat6(m: &Mat6) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

pub(crate) fn flat_se3(t: &Se3) -> Vec<f64> {
    t.to_rows().iter().flatten().copied().collect()
}

pub(crate) fn flat3(m: &DMat3) -> Vec<f64> {
    m.to_cols_array().to_vec()
}

/// A vector with coordinates in `[-r, r]`.
pub(crate) fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..=r, -r..=r, -r..=r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A unit vector, uniform in spherical coordinates.
pub(crate) fn unit_vec() -> impl Strategy<Value = DVec3> {
    (0.0..=PI, -PI..PI)
        .prop_map(|(t, p): (f64, f64)| DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()))
}

/// A rotation angle in `[0, π]`, with the hard cases (0, tiny, near π, π) drawn often.
pub(crate) fn angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.0..=PI,
        1 => Just(0.0),
        1 => 1e-12..1e-3,
        1 => (PI - 1e-3)..=PI,
        1 => Just(PI),
    ]
}

/// A rotation matrix about a random axis by an angle from [`angle`].
pub(crate) fn rotation() -> impl Strategy<Value = DMat3> {
    (unit_vec(), angle()).prop_map(|(axis, a)| rotation::rot_axis_angle(axis, a))
}

/// A rigid transform with translation in `[-2, 2]³`.
pub(crate) fn se3() -> impl Strategy<Value = Se3> {
    (rotation(), vec3(2.0)).prop_map(|(r, t)| Se3::new(r, t))
}

pub(crate) fn motion() -> impl Strategy<Value = Motion> {
    (vec3(2.0), vec3(2.0)).prop_map(|(l, a)| Motion::new(l, a))
}

pub(crate) fn force() -> impl Strategy<Value = Force> {
    (vec3(2.0), vec3(2.0)).prop_map(|(l, a)| Force::new(l, a))
}

/// A physically valid inertia: positive mass, centre of mass within 0.5 m, principal moments
/// that satisfy the triangle inequality, principal axes turned at random.
pub(crate) fn inertia() -> impl Strategy<Value = Inertia> {
    (
        0.01..10.0,
        vec3(0.5),
        0.01..1.0,
        0.01..1.0,
        0.0..=1.0,
        rotation(),
    )
        .prop_map(
            |(mass, com, a, b, s, r): (f64, DVec3, f64, f64, f64, DMat3)| {
                // The third moment lies between |a - b| and a + b.
                let c = (a - b).abs() + s * (a + b - (a - b).abs());
                let rotational = Symmetric3::from_diagonal(DVec3::new(a, b, c)).rotate(&r);
                Inertia::new(mass, com, rotational)
            },
        )
}
