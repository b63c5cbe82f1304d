//! MJCF models against MuJoCo 4.0 (`tests/data/reference/mjcf`, see its README): the compiled
//! tree (coordinate layout, inertias), then on every sample the body and site poses, the mass
//! matrix (without and with armature), the bias forces, inverse dynamics and body Jacobians,
//! after the documented mapping of MuJoCo's coordinates.

use kinetree_dynamics::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_joint_jacobians, frame_jacobian,
    update_frame_placements,
};
use kinetree_dynamics::model::Model;
use kinetree_dynamics::model::spatial::glam::{DMat3, DQuat, DVec3};
use kinetree_dynamics::model::spatial::{Motion, Symmetric3};
use kinetree_dynamics::{DynamicsData, JointTerms, crba, rnea};
use serde_json::Value;
use std::path::PathBuf;

/// Poses: absolute (m, and rotation-matrix entries).
const POSE_TOL: f64 = 1e-9;
/// M, bias, inverse dynamics, Jacobians: relative to the largest magnitude (at least 1).
const REL_TOL: f64 = 1e-9;

fn dir() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/mjcf"
    ))
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(numbers).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("not a number: {other}"),
    }
}

/// Every reference: (name, JSON, loaded model).
fn references() -> Vec<(String, Value, Model)> {
    let mut out = Vec::new();
    let mut entries: Vec<_> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    entries.sort();
    for path in entries {
        let reference: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let name = reference["name"].as_str().unwrap().to_string();
        let xml = dir().join(reference["xml"].as_str().unwrap());
        let model = Model::from_mjcf_file(&xml).unwrap_or_else(|e| panic!("{name}: {e}"));
        out.push((name, reference, model));
    }
    assert_eq!(out.len(), 12, "the 12 public MuJoCo references");
    out
}

/// MuJoCo's name of body `id`, or kinetree's name for an unnamed body.
fn body_name(reference: &Value, id: usize) -> String {
    let b = &reference["bodies"][id];
    b["name"]
        .as_str()
        .map_or_else(|| format!("body{id}"), str::to_string)
}

fn joint_name(reference: &Value, j: &Value) -> String {
    if let Some(n) = j["name"].as_str() {
        return n.to_string();
    }
    let body = j["body_id"].as_u64().unwrap() as usize;
    let k = j["id"].as_u64().unwrap() - reference["bodies"][body]["jntadr"].as_u64().unwrap();
    format!("{}:{k}", body_name(reference, body))
}

fn assert_close(what: &str, ours: &[f64], theirs: &[f64], tol: f64) {
    assert_eq!(ours.len(), theirs.len(), "{what}: length");
    let scale = theirs.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    for (k, (a, b)) in ours.iter().zip(theirs).enumerate() {
        assert!(
            (a - b).abs() <= tol * scale,
            "{what}[{k}]: {a} vs MuJoCo {b} (scale {scale})"
        );
    }
}

/// `G` with `v = G · qvel` at `qpos` (nv × nv, row-major), column by column through the model's
/// own conversion (which is linear in `qvel`).
fn velocity_map(model: &Model, qpos: &[f64]) -> Vec<f64> {
    let nv = model.nv();
    let mut g = vec![0.0; nv * nv];
    for j in 0..nv {
        let mut e = vec![0.0; nv];
        e[j] = 1.0;
        let col = model.v_from_mujoco(qpos, &e).unwrap();
        for i in 0..nv {
            g[i * nv + j] = col[i];
        }
    }
    g
}

/// `Gᵀ · M · G` (row-major): kinetree's mass matrix in MuJoCo's velocity coordinates.
fn to_mujoco_metric(m: &[f64], g: &[f64], nv: usize) -> Vec<f64> {
    let mut mg = vec![0.0; nv * nv];
    for i in 0..nv {
        for j in 0..nv {
            mg[i * nv + j] = (0..nv).map(|k| m[i * nv + k] * g[k * nv + j]).sum();
        }
    }
    let mut out = vec![0.0; nv * nv];
    for i in 0..nv {
        for j in 0..nv {
            out[i * nv + j] = (0..nv).map(|k| g[k * nv + i] * mg[k * nv + j]).sum();
        }
    }
    out
}

#[test]
fn the_tree_matches_mujocos_compiled_model() {
    for (name, reference, model) in references() {
        let size = |k: &str| reference[k].as_u64().unwrap() as usize;
        assert_eq!((model.nq(), model.nv()), (size("nq"), size("nv")), "{name}");
        let g = DVec3::from_slice(&numbers(&reference["gravity_effective"]));
        assert!((model.gravity() - g).length() == 0.0, "{name}: gravity");
        for j in reference["joints"].as_array().unwrap() {
            let jn = joint_name(&reference, j);
            let index = model
                .joint_index(&jn)
                .unwrap_or_else(|| panic!("{name}: joint {jn}"));
            assert_eq!(
                model.joint_q_range(index).start,
                j["qposadr"].as_u64().unwrap() as usize,
                "{name}: {jn} qposadr"
            );
            assert_eq!(
                model.joint_v_range(index).start,
                j["dofadr"].as_u64().unwrap() as usize,
                "{name}: {jn} dofadr"
            );
            let armature = numbers(&j["armature"]);
            assert!(
                (model.joint(index).dynamics.armature - armature[0]).abs() <= 1e-15,
                "{name}: {jn} armature"
            );
            if j["limited"].as_bool().unwrap() && j["type"] != "ball" {
                let range = numbers(&j["range"]);
                let limits = model.joint(index).limits;
                assert_close(
                    &format!("{name}: {jn} range"),
                    &[limits.lower, limits.upper],
                    &range,
                    1e-12,
                );
            }
        }
        // Each body's inertia (mass, centre of mass, rotational inertia about it in body axes).
        for (id, b) in reference["bodies"].as_array().unwrap().iter().enumerate() {
            let bn = body_name(&reference, id);
            let link = model
                .link_index(&bn)
                .unwrap_or_else(|| panic!("{name}: body {bn}"));
            let inertia = model.link(link).inertia();
            let mass = b["mass"].as_f64().unwrap();
            assert!(
                (inertia.mass - mass).abs() <= 1e-12 * mass.max(1.0),
                "{name}: {bn} mass {} vs {mass}",
                inertia.mass
            );
            if mass == 0.0 {
                continue;
            }
            let ipos = DVec3::from_slice(&numbers(&b["ipos"]));
            assert!(
                (inertia.com - ipos).length() <= 1e-12,
                "{name}: {bn} centre of mass"
            );
            let q = numbers(&b["iquat"]);
            let r = DMat3::from_quat(DQuat::from_xyzw(q[1], q[2], q[3], q[0]));
            let moments = DVec3::from_slice(&numbers(&b["inertia"]));
            let theirs = Symmetric3::from_diagonal(moments).rotate(&r);
            let scale = moments.max_element().max(1e-300);
            for (x, y) in inertia.rotational.to_voigt().iter().zip(theirs.to_voigt()) {
                assert!(
                    (x - y).abs() <= 1e-10 * scale,
                    "{name}: {bn} rotational inertia {:?} vs {:?}",
                    inertia.rotational,
                    theirs
                );
            }
        }
    }
}

#[test]
fn poses_dynamics_and_jacobians_match_mujoco() {
    for (name, reference, model) in references() {
        let nv = model.nv();
        let mut data = DynamicsData::new(&model);
        let mut with_armature = DynamicsData::with_joint_terms(&model, JointTerms::FromModel);
        let mut kin = KinematicsData::new(&model);
        let mut jac = vec![Motion::ZERO; nv];
        let nbody = reference["nbody"].as_u64().unwrap() as usize;
        let sites = reference["sites"].as_array().unwrap();
        for (s, sample) in reference["samples"].as_array().unwrap().iter().enumerate() {
            let what = |k: &str| format!("{name} sample {s}: {k}");
            let qpos = numbers(&sample["qpos"]);
            let qvel = numbers(&sample["qvel"]);
            let qacc = numbers(&sample["qacc"]);
            let q = model.q_from_mujoco(&qpos).unwrap();
            assert_eq!(model.q_to_mujoco(&q).unwrap(), qpos);

            // Body and site poses.
            compute_joint_jacobians(&model, &mut kin, &q).unwrap();
            update_frame_placements(&model, &mut kin).unwrap();
            let xpos = numbers(&sample["xpos"]);
            let xmat = numbers(&sample["xmat"]);
            for id in 0..nbody {
                let bn = body_name(&reference, id);
                let link = model.link_index(&bn).unwrap();
                let pose = kin.world_from(FrameId::Link(link)).unwrap();
                assert_close(
                    &what(&format!("xpos of {bn}")),
                    &pose.translation.to_array(),
                    &xpos[3 * id..3 * id + 3],
                    POSE_TOL,
                );
                let rows = pose.rotation_rows();
                assert_close(
                    &what(&format!("xmat of {bn}")),
                    rows.as_flattened(),
                    &xmat[9 * id..9 * id + 9],
                    POSE_TOL,
                );
            }
            let site_xpos = numbers(&sample["site_xpos"]);
            let site_xmat = numbers(&sample["site_xmat"]);
            for (k, site) in sites.iter().enumerate() {
                let sn = site["name"]
                    .as_str()
                    .map_or_else(|| format!("site{k}"), str::to_string);
                let bn = body_name(&reference, site["body_id"].as_u64().unwrap() as usize);
                let id = FrameId::find(&model, &format!("{bn}/{sn}")).unwrap();
                let pose = kin.world_from(id).unwrap();
                assert_close(
                    &what(&format!("site {sn}")),
                    &pose.translation.to_array(),
                    &site_xpos[3 * k..3 * k + 3],
                    POSE_TOL,
                );
                assert_close(
                    &what(&format!("site {sn} rotation")),
                    pose.rotation_rows().as_flattened(),
                    &site_xmat[9 * k..9 * k + 9],
                    POSE_TOL,
                );
            }

            // Mass matrix in MuJoCo's velocity coordinates, without and with armature.
            let g = velocity_map(&model, &qpos);
            let m = crba(&model, &mut data, &q).unwrap().to_vec();
            assert_close(
                &what("M"),
                &to_mujoco_metric(&m, &g, nv),
                &numbers(&sample["M"]),
                REL_TOL,
            );
            let m = crba(&model, &mut with_armature, &q).unwrap().to_vec();
            assert_close(
                &what("M with armature"),
                &to_mujoco_metric(&m, &g, nv),
                &numbers(&sample["M_armature"]),
                REL_TOL,
            );

            // Bias forces (qacc = 0) and inverse dynamics.
            let v = model.v_from_mujoco(&qpos, &qvel).unwrap();
            for (acc, key) in [(vec![0.0; nv], "qfrc_bias"), (qacc.clone(), "tau")] {
                let a = model.a_from_mujoco(&qpos, &qvel, &acc).unwrap();
                let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
                let ours = model.tau_to_mujoco(&q, &tau).unwrap();
                assert_close(&what(key), &ours, &numbers(&sample[key]), REL_TOL);
            }

            // World-frame Jacobians of body origins: J_mujoco = J_kinetree · G.
            for entry in sample["jac_body"].as_array().unwrap() {
                let bn = body_name(&reference, entry["body_id"].as_u64().unwrap() as usize);
                let link = model.link_index(&bn).unwrap();
                frame_jacobian(
                    &model,
                    &kin,
                    FrameId::Link(link),
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
                .unwrap();
                let (mut lin, mut ang) = (vec![0.0; 3 * nv], vec![0.0; 3 * nv]);
                for r in 0..3 {
                    for c in 0..nv {
                        for k in 0..nv {
                            lin[r * nv + c] += jac[k].linear[r] * g[k * nv + c];
                            ang[r * nv + c] += jac[k].angular[r] * g[k * nv + c];
                        }
                    }
                }
                assert_close(
                    &what(&format!("jacp of {bn}")),
                    &lin,
                    &numbers(&entry["jacp"]),
                    REL_TOL,
                );
                assert_close(
                    &what(&format!("jacr of {bn}")),
                    &ang,
                    &numbers(&entry["jacr"]),
                    REL_TOL,
                );
            }
        }
    }
}

#[test]
fn conversions_invert_each_other_and_keep_power() {
    for (name, reference, model) in references() {
        let sample = &reference["samples"][3];
        let qpos = numbers(&sample["qpos"]);
        let qvel = numbers(&sample["qvel"]);
        let qacc = numbers(&sample["qacc"]);
        let q = model.q_from_mujoco(&qpos).unwrap();
        let v = model.v_from_mujoco(&qpos, &qvel).unwrap();
        let a = model.a_from_mujoco(&qpos, &qvel, &qacc).unwrap();
        assert_close(&name, &model.v_to_mujoco(&q, &v).unwrap(), &qvel, 1e-14);
        assert_close(&name, &model.a_to_mujoco(&q, &v, &a).unwrap(), &qacc, 1e-13);
        // A force does the same work in both coordinates: tau · v = qfrc · qvel.
        let qfrc = numbers(&sample["tau"]);
        let tau = model.tau_from_mujoco(&qpos, &qfrc).unwrap();
        let power = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
        let (p1, p2) = (power(&tau, &v), power(&qfrc, &qvel));
        assert!(
            (p1 - p2).abs() <= 1e-12 * p2.abs().max(1.0),
            "{name}: power"
        );
        assert_close(&name, &model.tau_to_mujoco(&q, &tau).unwrap(), &qfrc, 1e-13);
    }
}

/// `model` written as MJCF and read back: every link where it was, and the same mass matrix and
/// inverse dynamics, joint by joint, on random states.
fn assert_same_after_mjcf_round_trip(name: &str, model: &Model) {
    use crate::common::{random_state, rng};
    let text = model
        .to_mjcf_string()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let back = Model::from_mjcf_str(&text).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
    assert_eq!((back.nq(), back.nv()), (model.nq(), model.nv()), "{name}");
    // Our v index → theirs, by joint name.
    let mut map_q = vec![0; model.nq()];
    let mut map_v = vec![0; model.nv()];
    for j in model.moving_joints() {
        let theirs = back
            .joint_index(&model.joint(j).name)
            .unwrap_or_else(|| panic!("{name}: joint {}", model.joint(j).name));
        for (a, b) in model.joint_q_range(j).zip(back.joint_q_range(theirs)) {
            map_q[a] = b;
        }
        for (a, b) in model.joint_v_range(j).zip(back.joint_v_range(theirs)) {
            map_v[a] = b;
        }
    }
    let (mut d1, mut d2) = (DynamicsData::new(model), DynamicsData::new(&back));
    let (mut k1, mut k2) = (KinematicsData::new(model), KinematicsData::new(&back));
    let mut r = rng(11);
    for _ in 0..5 {
        let (q, v, a) = random_state(model, &mut r);
        let permute = |x: &[f64], map: &[usize], n: usize| {
            let mut y = vec![0.0; n];
            for (k, &m) in map.iter().enumerate() {
                y[m] = x[k];
            }
            y
        };
        let (q2, v2, a2) = (
            permute(&q, &map_q, back.nq()),
            permute(&v, &map_v, back.nv()),
            permute(&a, &map_v, back.nv()),
        );
        compute_joint_jacobians(model, &mut k1, &q).unwrap();
        compute_joint_jacobians(&back, &mut k2, &q2).unwrap();
        for (l, link) in model.links().iter().enumerate() {
            // Empty massless links between joints are merged into the next body.
            let Some(theirs) = back.link_index(&link.name) else {
                assert!(
                    link.inertial.is_none() && link.visuals.is_empty(),
                    "{name}: link {} lost",
                    link.name
                );
                continue;
            };
            let (p1, p2) = (
                k1.world_from(FrameId::Link(l)).unwrap(),
                k2.world_from(FrameId::Link(theirs)).unwrap(),
            );
            assert!(p1.abs_diff_eq(p2, 1e-12, 1e-12), "{name}: {}", link.name);
        }
        let tau = rnea(model, &mut d1, &q, &v, &a).unwrap().to_vec();
        let tau2 = rnea(&back, &mut d2, &q2, &v2, &a2).unwrap().to_vec();
        let expected: Vec<f64> = map_v.iter().map(|&m| tau2[m]).collect();
        assert_close(&format!("{name}: rnea"), &tau, &expected, 1e-12);
        let m = crba(model, &mut d1, &q).unwrap().to_vec();
        let m2 = crba(&back, &mut d2, &q2).unwrap().to_vec();
        let nv = model.nv();
        let expected: Vec<f64> = (0..nv * nv)
            .map(|k| m2[map_v[k / nv] * nv + map_v[k % nv]])
            .collect();
        assert_close(&format!("{name}: crba"), &m, &expected, 1e-12);
    }
}

#[test]
fn models_written_as_mjcf_read_back_the_same() {
    for (name, _, model) in kinetree_test_support::robots() {
        match model.to_mjcf_string() {
            Ok(_) => assert_same_after_mjcf_round_trip(&name, &model),
            // MuJoCo refuses moving bodies without mass; the error names the joint.
            Err(e) => assert!(e.to_string().contains("no mass and inertia"), "{name}: {e}"),
        }
    }
    for (name, _, model) in references() {
        assert_same_after_mjcf_round_trip(&name, &model);
    }
}
