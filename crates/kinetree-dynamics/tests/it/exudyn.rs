//! Exudyn's spatial helpers: CRM/CRF against Featherstone's block formulas, and the
//! KinematicTree33 inertia about the joint by the parallel-axis theorem.

use kinetree_dynamics::exudyn::{
    crf, crm, inertia_from_tree33, mass_com_inertia_to_t66, tree33_inertia,
};
use kinetree_dynamics::spatial::glam::{DMat3, DVec3};
use kinetree_dynamics::spatial::{Force, Motion};

fn skew(a: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}

#[test]
fn crm_and_crf_are_featherstones_operators() {
    // v = [ω; v] in Featherstone's order.
    let v = [0.3, -1.2, 0.7, 2.0, 0.5, -0.4];
    let (w, l) = (skew([v[0], v[1], v[2]]), skew([v[3], v[4], v[5]]));
    let (m, f) = (crm(v), crf(v));
    for i in 0..3 {
        for j in 0..3 {
            // crm = [[ω×, 0], [v×, ω×]]; crf = [[ω×, v×], [0, ω×]].
            assert_eq!(m[i][j], w[i][j]);
            assert_eq!(m[i][j + 3], 0.0);
            assert_eq!(m[i + 3][j], l[i][j]);
            assert_eq!(m[i + 3][j + 3], w[i][j]);
            assert_eq!(f[i][j], w[i][j]);
            assert_eq!(f[i][j + 3], l[i][j]);
            assert_eq!(f[i + 3][j], 0.0);
            assert_eq!(f[i + 3][j + 3], w[i][j]);
        }
    }
    for i in 0..6 {
        for j in 0..6 {
            assert_eq!(f[i][j], -m[j][i]);
        }
    }
    // Applied to vectors they are kinetree's cross products (in the other order).
    let (a, b) = (
        [1.0, 2.0, -0.5, 0.1, -0.3, 0.8],
        [-0.2, 0.9, 1.1, 0.4, 0.0, -1.5],
    );
    let apply = |t: &[[f64; 6]; 6], x: [f64; 6]| -> [f64; 6] {
        core::array::from_fn(|i| (0..6).map(|j| t[i][j] * x[j]).sum())
    };
    let vm = Motion::from_featherstone(v);
    let expected = vm
        .cross_motion(&Motion::from_featherstone(a))
        .to_featherstone();
    let got = apply(&m, a);
    let expected_f = vm
        .cross_force(&Force::from_featherstone(b))
        .to_featherstone();
    let got_f = apply(&f, b);
    for i in 0..6 {
        assert!((got[i] - expected[i]).abs() < 1e-15);
        assert!((got_f[i] - expected_f[i]).abs() < 1e-15);
    }
}

#[test]
fn tree33_inertia_is_about_the_joint() {
    // 2 kg, centre of mass 0.5 m up z: about the joint the x and y moments grow by m·d² = 0.5.
    let (m, c) = (2.0, DVec3::new(0.0, 0.0, 0.5));
    let i_com = DMat3::from_diagonal(DVec3::new(0.1, 0.2, 0.3));
    let i_ref = tree33_inertia(m, c, i_com);
    assert!(i_ref.abs_diff_eq(DMat3::from_diagonal(DVec3::new(0.6, 0.7, 0.3)), 1e-15));
    assert!(inertia_from_tree33(m, c, i_ref).abs_diff_eq(i_com, 1e-15));
    // A general case: the upper-left block of the 6x6 inertia, and back.
    let c = DVec3::new(0.1, -0.25, 0.4);
    let i_com = DMat3::from_cols(
        DVec3::new(0.3, 0.01, -0.02),
        DVec3::new(0.01, 0.4, 0.03),
        DVec3::new(-0.02, 0.03, 0.5),
    );
    let i_ref = tree33_inertia(1.7, c, i_com);
    let t66 = mass_com_inertia_to_t66(1.7, c, i_com);
    for i in 0..3 {
        for j in 0..3 {
            assert!((i_ref.col(j)[i] - t66[i][j]).abs() < 1e-15);
        }
    }
    assert!(inertia_from_tree33(1.7, c, i_ref).abs_diff_eq(i_com, 1e-15));
}
