//! The fuzz harness shared by the libFuzzer targets (`fuzz/fuzz_targets/`, run with
//! `cargo fuzz`) and the stable `cargo test` cases (`tests/fuzz.rs`, which include this file).
//!
//! Every entry takes arbitrary bytes. The outcome must be `Ok` or a typed error: a panic is a
//! failure, and so is a non-finite number inside an `Ok` (the assertions below).

use kinetree::collision::{
    CollisionData, CollisionModel, CollisionOptions, compute_distances, compute_self_collisions,
};
use kinetree::dynamics::{DynamicsData, aba, crba, nonlinear_effects, rnea};
use kinetree::kinematics::spatial::Motion;
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, forward_kinematics,
};
use kinetree::model::{Model, RootJoint};

/// Models larger than this are only loaded, not run through the algorithms (keeps each input
/// fast; the loaders' scaling is tested elsewhere).
const MAX_BODIES: usize = 64;

/// URDF text → model (welded and floating root) → the algorithms.
pub fn urdf(bytes: &[u8]) {
    let Ok(text) = core::str::from_utf8(bytes) else {
        return;
    };
    for root in [RootJoint::Fixed, RootJoint::Floating] {
        if let Ok(model) = Model::from_urdf_str(text, root) {
            algorithms(&model, bytes);
        }
    }
}

/// MJCF text → model → the algorithms, and the MuJoCo coordinate conversions on a state made
/// of the input's bytes (every result finite or a typed error).
pub fn mjcf(bytes: &[u8]) {
    let Ok(text) = core::str::from_utf8(bytes) else {
        return;
    };
    let Ok(model) = Model::from_mjcf_str(text) else {
        return;
    };
    algorithms(&model, bytes);
    let qpos = kinetree::kinematics::configuration::neutral_configuration(&model);
    let qpos = model.q_to_mujoco(&qpos).expect("neutral q has nq entries");
    let qvel: Vec<f64> = (0..model.nv())
        .map(|k| f64::from(bytes[k % bytes.len()]) - 128.0)
        .collect();
    let q = model.q_from_mujoco(&qpos).expect("qpos has nq entries");
    let v = model.v_from_mujoco(&qpos, &qvel).expect("lengths match");
    let a = model
        .a_from_mujoco(&qpos, &qvel, &qvel)
        .expect("lengths match");
    let tau = model.tau_to_mujoco(&q, &a).expect("lengths match");
    for x in v.iter().chain(&a).chain(&tau) {
        assert!(x.is_finite(), "a MuJoCo conversion gave {x}");
    }
}

/// kinetree's JSON model text → model → the algorithms.
pub fn json(bytes: &[u8]) {
    let Ok(text) = core::str::from_utf8(bytes) else {
        return;
    };
    if let Ok(model) = Model::from_json_str(text, None) {
        algorithms(&model, bytes);
    }
}

/// A `kinetree compute` request (JSON text) against the Panda: parsed as the CLI does (a
/// `samples` array whose items may wrap their maps in `state`), evaluated, and the response
/// written back to JSON.
pub fn compute(bytes: &[u8]) {
    let Ok(request) = serde_json::from_slice::<serde_json::Value>(bytes) else {
        return;
    };
    let Some(samples) = request.get("samples").and_then(serde_json::Value::as_array) else {
        return;
    };
    let Ok(samples) = samples
        .iter()
        .map(|sample| {
            let state = match sample.get("state") {
                Some(state) if state.is_object() => state,
                _ => sample,
            };
            serde_json::from_value::<kinetree::batch::SampleInput>(state.clone())
        })
        .collect::<Result<Vec<_>, _>>()
    else {
        return;
    };
    let model = panda();
    for options in [
        kinetree::batch::BatchOptions::default(),
        kinetree::batch::BatchOptions {
            jacobians: vec!["panda_link8".to_string()],
            strict: true,
            ..Default::default()
        },
    ] {
        if let Ok(response) = kinetree::batch::evaluate(model, &samples, &options) {
            let json = serde_json::to_value(&response).expect("a batch output serializes");
            // serde_json writes NaN and infinities as null: an Ok response has none.
            assert!(!has_null_number(&json), "null in {json}");
        }
    }
}

/// The Panda (with collision spheres) and arbitrary bytes as q, v, a and τ.
pub fn state(bytes: &[u8]) {
    algorithms(panda(), bytes);
}

fn panda() -> &'static Model {
    static PANDA: std::sync::OnceLock<Model> = std::sync::OnceLock::new();
    PANDA.get_or_init(|| {
        Model::from_urdf_str(
            include_str!("../../tests/data/reference/urdf/panda_collision.urdf"),
            RootJoint::Fixed,
        )
        .expect("the Panda loads")
    })
}

/// Values drawn from bytes: a selector byte picks a special value (NaN, ±inf, ±0, subnormal,
/// ±1e308, ±1e-300), the raw bits of the next 8 bytes, or a small value.
struct Values<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Values<'_> {
    fn next(&mut self) -> f64 {
        if self.bytes.is_empty() {
            return 0.0;
        }
        let byte = |v: &mut Self| {
            let b = v.bytes[v.at % v.bytes.len()];
            v.at += 1;
            b
        };
        let selector = byte(self);
        match selector {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => -0.0,
            4 => 5e-324,
            5 => 1e308,
            6 => -1e308,
            7 => 1e-300,
            8..=15 => {
                let mut raw = [0u8; 8];
                for r in &mut raw {
                    *r = byte(self);
                }
                f64::from_le_bytes(raw)
            }
            _ => (f64::from(selector) - 136.0) / 16.0,
        }
    }
}

/// Runs the algorithms on `model` with a state drawn from `bytes`; asserts that every `Ok`
/// result is finite.
pub fn algorithms(model: &Model, bytes: &[u8]) {
    if model.bodies().len() > MAX_BODIES {
        return;
    }
    let mut values = Values { bytes, at: 0 };
    let mut q = kinetree::kinematics::configuration::neutral_configuration(model);
    // Every other coordinate drawn from the bytes, the rest left neutral, so that both the
    // entry checks and the sweeps are reached.
    for (k, x) in q.iter_mut().enumerate() {
        let v = values.next();
        if k % 2 == 0 || v.is_finite() {
            *x = v;
        }
    }
    let nv = model.nv();
    let v: Vec<f64> = (0..nv).map(|_| values.next()).collect();
    let a: Vec<f64> = (0..nv).map(|_| values.next()).collect();
    let tau: Vec<f64> = (0..nv).map(|_| values.next()).collect();

    let mut kd = KinematicsData::new(model);
    if forward_kinematics(model, &mut kd, &q).is_ok() {
        assert!(
            kd.world_from_link().iter().all(|x| x.is_finite()),
            "non-finite placement in an Ok"
        );
    }
    let mut jac = vec![Motion::ZERO; nv];
    let last = FrameId::Link(model.links().len().saturating_sub(1));
    if compute_frame_jacobian(model, &mut kd, &q, last, ReferenceFrame::World, &mut jac).is_ok() {
        assert!(
            jac.iter().all(Motion::is_finite),
            "non-finite Jacobian in an Ok"
        );
    }

    let mut dd = DynamicsData::new(model);
    let finite = |r: Result<&[f64], _>, what: &str| {
        if let Ok(x) = r {
            assert!(
                x.iter().all(|y: &f64| y.is_finite()),
                "non-finite {what} in an Ok"
            );
        }
    };
    finite(rnea(model, &mut dd, &q, &v, &a), "rnea");
    finite(nonlinear_effects(model, &mut dd, &q, &v), "nle");
    finite(crba(model, &mut dd, &q), "crba");
    finite(aba(model, &mut dd, &q, &v, &tau), "aba");

    let options = CollisionOptions::default().skip_missing_meshes();
    if let Ok(cmodel) = CollisionModel::from_model(model, &options) {
        let mut cd = CollisionData::new(&cmodel);
        if cd.compute_placements(model, &cmodel, &mut kd, &q).is_ok() {
            if let Ok(d) = compute_distances(&cmodel, &mut cd) {
                assert!(
                    d.iter().all(|p| !p.distance.is_nan()),
                    "NaN distance in an Ok"
                );
            }
            if let Ok(c) = compute_self_collisions(&cmodel, &mut cd) {
                for p in c {
                    assert!(p.distance <= 0.0, "a listed contact is separated: {p:?}");
                }
            }
        }
    }
}

fn has_null_number(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Null => true,
        serde_json::Value::Array(a) => a.iter().any(has_null_number),
        serde_json::Value::Object(o) => o.values().any(has_null_number),
        _ => false,
    }
}

/// yapCAD chain JSON text → model, the joint values stored in the file and the exported world
/// poses → forward kinematics at the stored values, then the algorithms. Returns whether the
/// text loaded (so the stable tests can check that the generated inputs reach the algorithms).
pub fn yapcad(bytes: &[u8]) -> bool {
    let Ok(text) = core::str::from_utf8(bytes) else {
        return false;
    };
    let Ok(chain) = Model::from_yapcad_str(text) else {
        return false;
    };
    let model = &chain.model;
    assert_eq!(
        chain.q.len(),
        model.nq(),
        "stored values of the wrong length"
    );
    assert!(
        chain.q.iter().all(|x| x.is_finite()),
        "non-finite stored joint value in an Ok: {:?}",
        chain.q
    );
    assert!(
        chain.world_poses.iter().flatten().all(|x| x.is_finite()),
        "non-finite exported pose in an Ok"
    );
    if model.bodies().len() <= MAX_BODIES {
        let mut kd = KinematicsData::new(model);
        if forward_kinematics(model, &mut kd, &chain.q).is_ok() {
            assert!(
                kd.world_from_link().iter().all(|x| x.is_finite()),
                "non-finite placement at the stored values in an Ok"
            );
        }
    }
    algorithms(model, bytes);
    true
}
