//! SDFormat models against their references (`tests/data/reference/sdf`, see its README):
//! the 7 reference URDF robots converted by libsdformat 12 against the Pinocchio references of
//! the original URDFs (link poses, mass matrix, RNEA, nonlinear effects, gravity), and the 8
//! SDFormat models Drake ships against Drake (body poses, inertias, mass matrix, bias term,
//! gravity forces and inverse dynamics, after mapping Drake's floating-joint coordinates).

use kinetree_dynamics::kinematics::configuration::{Space, from_named};
use kinetree_dynamics::kinematics::{FrameId, KinematicsData, forward_kinematics};
use kinetree_dynamics::model::sdf::{SdfModel, SdfOptions, load_sdf_file};
use kinetree_dynamics::model::spatial::Se3;
use kinetree_dynamics::model::spatial::glam::{DMat3, DQuat, DVec3};
use kinetree_dynamics::model::{JointKind, Model, RootJoint};
use kinetree_dynamics::{DynamicsData, compute_all_terms, crba, generalized_gravity, rnea};
use kinetree_test_support::{reference_dir, values};
use serde_json::Value;
use std::path::PathBuf;

/// Poses: absolute (m, and rotation-matrix entries).
const POSE_TOL: f64 = 1e-9;
/// M, bias, inverse dynamics: relative to the largest magnitude (at least 1).
const REL_TOL: f64 = 1e-9;

fn dir() -> PathBuf {
    reference_dir().join("sdf")
}

fn read_json(path: PathBuf) -> Value {
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(numbers).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("not a number: {other}"),
    }
}

/// A pose stored as `translation` (or `xyz`) and a row-major `rotation`.
fn pose(v: &Value) -> Se3 {
    let t = if v["translation"].is_null() {
        &v["xyz"]
    } else {
        &v["translation"]
    };
    let r = numbers(&v["rotation"]);
    Se3::new(
        DMat3::from_cols_array(&[r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]]),
        DVec3::from_slice(&numbers(t)),
    )
}

/// The largest difference between two poses (translation and rotation entries).
fn pose_error(a: &Se3, b: &Se3) -> f64 {
    let dt = (a.translation - b.translation).abs().max_element();
    let dr = (a.rotation - b.rotation)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    dt.max(dr)
}

/// The largest difference relative to the largest magnitude of `theirs` (at least 1).
fn relative(ours: &[f64], theirs: &[f64]) -> f64 {
    assert_eq!(ours.len(), theirs.len());
    let scale = theirs.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    ours.iter()
        .zip(theirs)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

fn link_pose(model: &Model, kin: &KinematicsData, name: &str) -> Se3 {
    let link = model
        .link_index(name)
        .unwrap_or_else(|| panic!("no link {name}"));
    *kin.world_from(FrameId::Link(link)).unwrap()
}

/// The converted robots with an SDFormat file: (robot, variant, libsdformat JSON, Pinocchio
/// JSON).
fn converted() -> Vec<(String, String, Value, Value)> {
    let mut out = Vec::new();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir().join("converted"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "json")
                && !["index.json", "drake_crosscheck.json"]
                    .contains(&p.file_name().unwrap().to_str().unwrap())
        })
        .collect();
    paths.sort();
    for path in paths {
        let r = read_json(path);
        let robot = r["robot"].as_str().unwrap().to_string();
        let pinocchio = read_json(reference_dir().join(format!("{robot}.json")));
        for variant in ["lumped", "preserved"] {
            if r["variants"][variant]["sdf"].is_string() {
                out.push((
                    robot.clone(),
                    variant.to_string(),
                    r.clone(),
                    pinocchio.clone(),
                ));
            }
        }
    }
    assert_eq!(out.len(), 12, "7 lumped and 5 preserved converted files");
    out
}

#[test]
fn converted_urdfs_match_pinocchio() {
    let mut report = String::new();
    for (robot, variant, r, pin) in converted() {
        let what = format!("{robot} ({variant})");
        let v = &r["variants"][variant.as_str()];
        let free = r["root_joint_of_reference"] == "free_flyer";
        let options = SdfOptions {
            free_trees: if free {
                RootJoint::Floating
            } else {
                RootJoint::Fixed
            },
            ..SdfOptions::default()
        };
        let path = dir().join("converted").join(v["sdf"].as_str().unwrap());
        let SdfModel { model, q0 } =
            load_sdf_file(&path, &options).unwrap_or_else(|e| panic!("{what}: {e}"));
        let root = r["urdf_root_link"].as_str().unwrap();
        // Pinocchio's free-flyer is `root_joint`; ours is named after the root link.
        let rename = |name: &str| {
            if name == "root_joint" {
                root.to_string()
            } else {
                name.to_string()
            }
        };
        let mass = model.total_mass();
        let expected = v["summary"]["sdf_total_mass"].as_f64().unwrap();
        assert!(
            (mass - expected).abs() <= 1e-12 * expected,
            "{what}: mass {mass} vs {expected}"
        );

        // Link poses at the zero configuration, and where the lumped URDF links sit.
        let mut kin = KinematicsData::new(&model);
        forward_kinematics(&model, &mut kin, &q0).unwrap();
        let mut worst_pose = 0.0f64;
        for l in v["links"].as_array().unwrap() {
            let name = l["name"].as_str().unwrap();
            let e = pose_error(&link_pose(&model, &kin, name), &pose(&l["pose_in_model"]));
            worst_pose = worst_pose.max(e);
        }
        for (name, l) in v["urdf_links"].as_object().unwrap() {
            if l["fate"] == "lumped" {
                let host = l["sdf_link"].as_str().unwrap();
                let ours = link_pose(&model, &kin, host) * pose(&l["pose_in_sdf_link"]);
                let e = pose_error(&ours, &pose(&l["pose_in_model"]));
                assert!(e <= POSE_TOL, "{what}: lumped link {name} pose error {e:e}");
            }
        }
        assert!(
            worst_pose <= POSE_TOL,
            "{what}: link pose error {worst_pose:e}"
        );

        // Joint kinds and limits as libsdformat read them.
        for j in v["joints"].as_array().unwrap() {
            let name = j["name"].as_str().unwrap();
            let joint = model.joint(model.joint_index(name).unwrap());
            let kind = match j["type"].as_str().unwrap() {
                "revolute" if j["unbounded"] == true => JointKind::Continuous,
                "revolute" => JointKind::Revolute,
                "prismatic" => JointKind::Prismatic,
                "fixed" => JointKind::Fixed,
                other => panic!("{what}: joint type {other}"),
            };
            assert_eq!(joint.kind, kind, "{what}: {name}");
            if kind.has_position_limits() {
                let (lo, hi) = (j["lower"].as_f64().unwrap(), j["upper"].as_f64().unwrap());
                assert_eq!(
                    (joint.limits.lower, joint.limits.upper),
                    (lo, hi),
                    "{what}: {name}"
                );
            }
            if kind.is_moving() {
                let axis = DVec3::from_slice(&numbers(&j["axis_in_joint_frame"]));
                assert!((joint.axis - axis).length() <= 1e-15, "{what}: {name} axis");
            }
        }

        let checks = &v["checks"]["dynamics_vs_pinocchio"];
        if checks["equivalent_within_1e-9"] != true {
            // libsdformat dropped massive links with their joints: the README's numbers are
            // what it says, the dropped joints are absent, and the others are all there.
            for j in checks["joints_missing_in_sdf"].as_array().unwrap() {
                let name = j.as_str().unwrap();
                assert!(model.joint_index(name).is_none(), "{what}: {name}");
            }
            let lost = v["summary"]["mass_lost"].as_f64().unwrap();
            let urdf_mass = r["urdf_total_mass"].as_f64().unwrap();
            assert!(
                (urdf_mass - mass - lost).abs() <= 1e-9,
                "{what}: mass lost {}",
                urdf_mass - mass
            );
            assert_eq!(
                model.nv(),
                checks["nv_sdf"].as_u64().unwrap() as usize,
                "{what}"
            );
            report.push_str(&format!(
                "{what:>28}: poses {worst_pose:.1e}; not equivalent (mass lost {lost:.2} kg)\n"
            ));
            continue;
        }

        // Dynamics on Pinocchio's samples.
        assert_eq!(model.nv(), pin["nv"].as_u64().unwrap() as usize, "{what}");
        let nv = model.nv();
        let mut map = vec![usize::MAX; nv];
        for j in pin["joints"].as_array().unwrap() {
            let ours = model.joint_v_range(
                model
                    .joint_index(&rename(j["name"].as_str().unwrap()))
                    .unwrap(),
            );
            let theirs = j["idx_v"].as_u64().unwrap() as usize;
            for (k, o) in ours.enumerate() {
                map[theirs + k] = o;
            }
        }
        let named = |sample: &Value, key: &str, space: Space| -> Vec<f64> {
            let values_of = sample["state"][key].as_object().unwrap();
            from_named(
                &model,
                space,
                values_of.iter().map(|(n, x)| (rename(n), values(x))),
                false,
            )
            .unwrap()
        };
        let mut data = DynamicsData::new(&model);
        let mut worst = [0.0f64; 5];
        for sample in pin["samples"].as_array().unwrap() {
            let q = named(sample, "q", Space::Configuration);
            let (vel, acc, tau) = (
                named(sample, "v", Space::Velocity),
                named(sample, "a", Space::Velocity),
                named(sample, "tau", Space::Velocity),
            );
            let all = compute_all_terms(&model, &mut data, &q, &vel, &acc, &tau).unwrap();
            for (k, (ours, key)) in [
                (&all.rnea, "rnea"),
                (&all.nle, "nle"),
                (&all.gravity_torque, "gravity_torque"),
            ]
            .into_iter()
            .enumerate()
            {
                let mapped: Vec<f64> = (0..nv).map(|i| ours[map[i]]).collect();
                worst[k] = worst[k].max(relative(&mapped, &numbers(&sample[key])));
            }
            let theirs = numbers(&sample["mass_matrix"]);
            let ours: Vec<f64> = (0..nv * nv)
                .map(|k| all.mass_matrix[map[k / nv] * nv + map[k % nv]])
                .collect();
            worst[3] = worst[3].max(relative(&ours, &theirs));
            // Every URDF link the converter kept or merged, where Pinocchio puts it.
            forward_kinematics(&model, &mut kin, &q).unwrap();
            for (name, l) in v["urdf_links"].as_object().unwrap() {
                let host = match l["fate"].as_str().unwrap() {
                    "link" => name.as_str(),
                    "lumped" => l["sdf_link"].as_str().unwrap(),
                    _ => continue,
                };
                let ours = link_pose(&model, &kin, host) * pose(&l["pose_in_sdf_link"]);
                let e = pose_error(&ours, &pose(&sample["link_poses"][name]));
                worst[4] = worst[4].max(e);
            }
        }
        let names = ["rnea", "nle", "gravity", "M", "link poses"];
        for (n, w) in names.iter().zip(worst) {
            let tol = if *n == "link poses" {
                POSE_TOL
            } else {
                REL_TOL
            };
            assert!(w <= tol, "{what}: {n} error {w:e}");
        }
        report.push_str(&format!(
            "{what:>28}: poses {worst_pose:.1e}; {}\n",
            names
                .iter()
                .zip(worst)
                .map(|(n, w)| format!("{n} {w:.1e}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    eprintln!("converted SDFormat files against Pinocchio:\n{report}");
}

/// A Drake joint mapped onto ours.
struct Mapped {
    floating: bool,
    /// Drake's position and velocity starts, ours.
    drake: (usize, usize),
    ours: (usize, usize),
}

fn drake_joints(name: &str, reference: &Value, model: &Model) -> Vec<Mapped> {
    let mut out = Vec::new();
    for j in reference["joints"].as_array().unwrap() {
        let kind = j["type"].as_str().unwrap();
        if kind == "weld" {
            continue;
        }
        let jn = j["name"].as_str().unwrap();
        let index = model
            .joint_index(jn)
            .unwrap_or_else(|| panic!("{name}: joint {jn}"));
        let ours = model.joint(index);
        let expected = match kind {
            "quaternion_floating" => vec![JointKind::Floating],
            "revolute" => vec![JointKind::Revolute, JointKind::Continuous],
            "prismatic" => vec![JointKind::Prismatic],
            other => panic!("{name}: Drake joint type {other}"),
        };
        assert!(
            expected.contains(&ours.kind),
            "{name}: {jn} is {:?}",
            ours.kind
        );
        if kind != "quaternion_floating" {
            let damping = j["damping"].as_f64().unwrap();
            assert!(
                (ours.dynamics.damping - damping).abs() <= 1e-15,
                "{name}: {jn} damping"
            );
            let lo = &j["position_lower_limits"][0];
            let hi = &j["position_upper_limits"][0];
            let (l, u) = (ours.limits.lower, ours.limits.upper);
            assert_eq!(lo.as_f64().unwrap_or(f64::NEG_INFINITY), l, "{name}: {jn}");
            assert_eq!(hi.as_f64().unwrap_or(f64::INFINITY), u, "{name}: {jn}");
        } else {
            assert_eq!(
                j["child_body"].as_str().unwrap(),
                jn,
                "{name}: floating joint name"
            );
        }
        out.push(Mapped {
            floating: kind == "quaternion_floating",
            drake: (
                j["position_start"].as_u64().unwrap() as usize,
                j["velocity_start"].as_u64().unwrap() as usize,
            ),
            ours: (
                model.joint_q_range(index).start,
                model.joint_v_range(index).start,
            ),
        });
    }
    out
}

/// Our `q` for Drake's: a floating joint's `[qw, qx, qy, qz, x, y, z]` becomes
/// `[x, y, z, qx, qy, qz, qw]`.
fn q_from_drake(joints: &[Mapped], nq: usize, qd: &[f64]) -> Vec<f64> {
    let mut q = vec![0.0; nq];
    for j in joints {
        let (d, o) = (j.drake.0, j.ours.0);
        if j.floating {
            q[o..o + 7].copy_from_slice(&[
                qd[d + 4],
                qd[d + 5],
                qd[d + 6],
                qd[d + 1],
                qd[d + 2],
                qd[d + 3],
                qd[d],
            ]);
        } else {
            q[o] = qd[d];
        }
    }
    q
}

/// The rotation of a floating joint's body in the world, from our `q`.
fn rotation(q: &[f64], at: usize) -> DMat3 {
    DMat3::from_quat(DQuat::from_xyzw(q[at + 3], q[at + 4], q[at + 5], q[at + 6]).normalize())
}

/// Our `v` for Drake's: `[ω_W; v_W]` becomes `[Rᵀ v_W; Rᵀ ω_W]` (both in the body frame).
fn v_from_drake(joints: &[Mapped], nv: usize, q: &[f64], vd: &[f64]) -> Vec<f64> {
    let mut v = vec![0.0; nv];
    for j in joints {
        let (d, o) = (j.drake.1, j.ours.1);
        if j.floating {
            let rt = rotation(q, j.ours.0).transpose();
            let w = rt * DVec3::from_slice(&vd[d..d + 3]);
            let lin = rt * DVec3::from_slice(&vd[d + 3..d + 6]);
            v[o..o + 3].copy_from_slice(&lin.to_array());
            v[o + 3..o + 6].copy_from_slice(&w.to_array());
        } else {
            v[o] = vd[d];
        }
    }
    v
}

/// Our `a` for Drake's `v̇` at `q`, `v` (ours): the derivative of the body-frame velocity,
/// `a_lin = Rᵀ v̇_W − ω_B × v_B`, `a_ang = Rᵀ ω̇_W`.
fn a_from_drake(joints: &[Mapped], nv: usize, q: &[f64], v: &[f64], ad: &[f64]) -> Vec<f64> {
    let mut a = v_from_drake(joints, nv, q, ad);
    for j in joints.iter().filter(|j| j.floating) {
        let o = j.ours.1;
        let lin = DVec3::from_slice(&v[o..o + 3]);
        let w = DVec3::from_slice(&v[o + 3..o + 6]);
        let t = w.cross(lin);
        for k in 0..3 {
            a[o + k] -= t[k];
        }
    }
    a
}

/// `G` with `v = G · v_drake` (row-major `nv × nv`).
fn velocity_map(joints: &[Mapped], nv: usize, q: &[f64]) -> Vec<f64> {
    let mut g = vec![0.0; nv * nv];
    for c in 0..nv {
        let mut e = vec![0.0; nv];
        e[c] = 1.0;
        let col = v_from_drake(joints, nv, q, &e);
        for r in 0..nv {
            g[r * nv + c] = col[r];
        }
    }
    g
}

/// `Gᵀ · x`: a generalized force in Drake's coordinates (same power).
fn force_to_drake(g: &[f64], x: &[f64]) -> Vec<f64> {
    let nv = x.len();
    (0..nv)
        .map(|c| (0..nv).map(|r| g[r * nv + c] * x[r]).sum())
        .collect()
}

#[test]
fn drake_models_match_drake() {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir().join("drake"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json") && !p.ends_with("index.json"))
        .collect();
    paths.sort();
    assert_eq!(paths.len(), 8, "the 8 SDFormat models Drake ships");
    let mut report = String::new();
    for path in paths {
        let reference = read_json(path);
        let name = reference["name"].as_str().unwrap().to_string();
        let sdf = dir().join("drake").join(reference["sdf"].as_str().unwrap());
        let SdfModel { model, q0 } =
            load_sdf_file(&sdf, &SdfOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (nq, nv) = (model.nq(), model.nv());
        assert_eq!(
            (nq, nv),
            (
                reference["nq"].as_u64().unwrap() as usize,
                reference["nv"].as_u64().unwrap() as usize
            ),
            "{name}"
        );
        let joints = drake_joints(&name, &reference, &model);
        // The initial configuration is Drake's default one.
        let q0_drake = q_from_drake(&joints, nq, &numbers(&reference["q0"]));
        assert!(relative(&q0, &q0_drake) <= 1e-15, "{name}: q0 {q0:?}");

        // Inertias.
        for b in reference["bodies"].as_array().unwrap().iter().skip(1) {
            let bn = b["name"].as_str().unwrap();
            let link = model.link_index(bn).unwrap();
            let inertia = model.link(link).inertia();
            let mass = b["mass"].as_f64().unwrap();
            assert!(
                (inertia.mass - mass).abs() <= 1e-15 * mass.max(1.0),
                "{name}: {bn}"
            );
            let com = DVec3::from_slice(&numbers(&b["com_in_body"]));
            assert!((inertia.com - com).length() <= 1e-15, "{name}: {bn} com");
            let i = numbers(&b["rotational_inertia_about_com"]);
            let ours = inertia.rotational.to_mat3().to_cols_array();
            assert!(relative(&ours, &i) <= 1e-12, "{name}: {bn} inertia");
        }

        let mut kin = KinematicsData::new(&model);
        let check_poses = |kin: &KinematicsData, poses: &Value| -> f64 {
            let mut worst = 0.0f64;
            for (bn, p) in poses.as_object().unwrap() {
                if bn == "world" {
                    continue;
                }
                worst = worst.max(pose_error(&link_pose(&model, kin, bn), &pose(p)));
            }
            worst
        };
        forward_kinematics(&model, &mut kin, &q0).unwrap();
        // Joint axes in the world at q0: Drake's in its frame F on the parent body, ours in the
        // frame of the joint's child link.
        for j in reference["joints"].as_array().unwrap() {
            if !["revolute", "prismatic"].contains(&j["type"].as_str().unwrap()) {
                continue;
            }
            let parent = &reference["body_poses_at_q0"][j["parent_body"].as_str().unwrap()];
            let theirs = (pose(parent) * pose(&j["X_PF"])).rotation
                * DVec3::from_slice(&numbers(&j["axis_in_F"]));
            let joint = model.joint(model.joint_index(j["name"].as_str().unwrap()).unwrap());
            let ours = kin.world_from_link()[joint.child_link].rotation * joint.axis;
            assert!(
                (ours - theirs).length() <= 1e-12,
                "{name}: {} axis",
                joint.name
            );
        }
        let mut worst = [
            check_poses(&kin, &reference["body_poses_at_q0"]),
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        let mut data = DynamicsData::new(&model);
        for sample in reference["samples"].as_array().unwrap() {
            let q = q_from_drake(&joints, nq, &numbers(&sample["q"]));
            let v = v_from_drake(&joints, nv, &q, &numbers(&sample["v"]));
            forward_kinematics(&model, &mut kin, &q).unwrap();
            worst[0] = worst[0].max(check_poses(&kin, &sample["body_poses"]));
            if nv == 0 {
                continue;
            }
            let g = velocity_map(&joints, nv, &q);
            // Mass matrix: Gᵀ M G.
            let m = crba(&model, &mut data, &q).unwrap().to_vec();
            let mut m_drake = vec![0.0; nv * nv];
            for r in 0..nv {
                for c in 0..nv {
                    m_drake[r * nv + c] = (0..nv)
                        .map(|i| {
                            g[i * nv + r]
                                * (0..nv).map(|k| m[i * nv + k] * g[k * nv + c]).sum::<f64>()
                        })
                        .sum();
                }
            }
            worst[1] = worst[1].max(relative(&m_drake, &numbers(&sample["mass_matrix"])));
            // Gravity: Drake's τ_g is the force gravity applies, −g(q).
            let grav = generalized_gravity(&model, &mut data, &q).unwrap().to_vec();
            let tau_g: Vec<f64> = force_to_drake(&g, &grav).iter().map(|x| -x).collect();
            worst[2] = worst[2].max(relative(
                &tau_g,
                &numbers(&sample["gravity_generalized_forces"]),
            ));
            // Bias (v̇ = 0) and inverse dynamics, both without gravity.
            for (key, vdot, slot) in [
                ("bias", vec![0.0; nv], 3),
                ("inverse_dynamics", numbers(&sample["vdot"]), 4),
            ] {
                let a = a_from_drake(&joints, nv, &q, &v, &vdot);
                let tau = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
                let no_gravity: Vec<f64> = tau.iter().zip(&grav).map(|(t, g)| t - g).collect();
                let ours = force_to_drake(&g, &no_gravity);
                worst[slot] = worst[slot].max(relative(&ours, &numbers(&sample[key])));
            }
        }
        let names = ["poses", "M", "gravity", "bias", "inverse dynamics"];
        for (n, w) in names.iter().zip(worst) {
            let tol = if *n == "poses" { POSE_TOL } else { REL_TOL };
            assert!(w <= tol, "{name}: {n} error {w:e}");
        }
        report.push_str(&format!(
            "{name:>48}: {}\n",
            names
                .iter()
                .zip(worst)
                .map(|(n, w)| format!("{n} {w:.1e}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    eprintln!("Drake's SDFormat models against Drake:\n{report}");
}
