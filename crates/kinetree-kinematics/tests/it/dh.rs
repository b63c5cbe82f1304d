//! Denavit–Hartenberg tables: the row matrix against the textbook formula, and JSON tables
//! (standard and modified, SI and mm/deg) whose forward kinematics is the product of the rows.

use kinetree_kinematics::model::Model;
use kinetree_kinematics::model::dh::{DhConvention, DhRow, DhTable};
use kinetree_kinematics::{FrameId, KinematicsData, forward_kinematics, update_frame_placements};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// The standard DH matrix as textbooks print it.
fn textbook(a: f64, alpha: f64, d: f64, theta: f64) -> [[f64; 4]; 4] {
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = alpha.sin_cos();
    [
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

#[test]
fn a_row_is_the_textbook_matrix() {
    let mut rng = SmallRng::seed_from_u64(11);
    for _ in 0..50 {
        let [a, alpha, d, theta, q] = [0; 5].map(|_| rng.random_range(-2.0..2.0));
        let m = DhRow::revolute(a, alpha, d, theta).transform(q).to_rows();
        let p = DhRow::prismatic(a, alpha, d, theta).transform(q).to_rows();
        let (rev, pri) = (
            textbook(a, alpha, d, theta + q),
            textbook(a, alpha, d + q, theta),
        );
        for i in 0..4 {
            for j in 0..4 {
                assert!((m[i][j] - rev[i][j]).abs() < 1e-14, "{m:?} vs {rev:?}");
                assert!((p[i][j] - pri[i][j]).abs() < 1e-14, "{p:?} vs {pri:?}");
            }
        }
    }
}

/// A three-row table in mm/deg as JSON, both conventions: the model's `dh3` frame is where the
/// product of the rows (in metres) puts it, at random joint values.
#[test]
fn json_tables_build_arms_whose_fk_is_the_row_product() {
    for convention in ["standard", "modified"] {
        let json = format!(
            r#"{{"name": "arm", "convention": "{convention}",
              "units": {{"length": "mm", "angle": "deg"}},
              "dh": [
                {{"a": 0, "alpha": 90, "d": 330, "theta": 0, "joint": "waist",
                  "limits": {{"lower": -170, "upper": 170}}}},
                {{"type": "prismatic", "a": 260, "alpha": -90, "d": 20, "theta": 30}},
                {{"type": "continuous", "a": 25, "alpha": 90, "d": 0, "theta": -90,
                  "inertial": {{"mass": 2, "com": [10, 0, 0], "inertia": {{"ixx": 1000}}}}}}
              ]}}"#
        );
        let table = DhTable::from_json_str(&json).unwrap();
        assert_eq!(
            table.convention,
            if convention == "standard" {
                DhConvention::Standard
            } else {
                DhConvention::Modified
            }
        );
        let model = Model::from_json_str(&json, None).unwrap();
        assert_eq!(model.nq(), 3);
        let waist = model.joint(model.joint_index("waist").unwrap());
        assert!((waist.limits.upper - 170f64.to_radians()).abs() < 1e-15);
        let mut data = KinematicsData::new(&model);
        let dh3 = FrameId::find(&model, "dh3").unwrap();
        let mut rng = SmallRng::seed_from_u64(5);
        for _ in 0..20 {
            let q = [0; 3].map(|_| rng.random_range(-1.5..1.5));
            forward_kinematics(&model, &mut data, &q).unwrap();
            update_frame_placements(&model, &mut data).unwrap();
            let fk = *data.world_from(dh3).unwrap();
            let product = table.transform(&q).unwrap();
            let by_rows = table.rows.iter().zip(q).fold(
                kinetree_kinematics::spatial::Se3::IDENTITY,
                |t, (row, x)| t * row.transform_in(table.convention, x),
            );
            assert!(
                (fk.translation - product.translation).length() < 1e-12,
                "{convention}"
            );
            assert!(
                fk.rotation.abs_diff_eq(product.rotation, 1e-12),
                "{convention}"
            );
            assert!((by_rows.translation - product.translation).length() < 1e-15);
        }
    }
    // Unknown fields, types and conventions are errors naming what is wrong.
    for (bad, word) in [
        (r#"{"dh": [{"a": 1, "lenght": 2}]}"#, "lenght"),
        (r#"{"dh": [{"type": "spherical"}]}"#, "spherical"),
        (r#"{"convention": "craig", "dh": []}"#, "craig"),
    ] {
        let e = Model::from_json_str(bad, None).unwrap_err();
        assert!(e.to_string().contains(word), "{e}");
    }
    assert!(
        DhTable::new("t", DhConvention::Standard)
            .transform(&[1.0])
            .is_err()
    );
}
