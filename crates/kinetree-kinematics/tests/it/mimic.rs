//! Coupled mimic joints (`MimicMode::Coupled`) on panda, whose second finger mimics the first.

use kinetree_kinematics::configuration::{integrate, random_configuration, set_joint_q};
use kinetree_kinematics::model::{Issue, LoadOptions, MimicMode, Model, ModelError, RootJoint};
use kinetree_kinematics::spatial::{Motion, explog};
use kinetree_kinematics::{
    FrameId, KinematicsData, KinematicsError, ReferenceFrame, change_reference,
    compute_frame_jacobian, compute_joint_jacobians, compute_joint_jacobians_time_variation,
    forward_kinematics, frame_jacobian, frame_jacobian_time_variation,
};
use rand::SeedableRng;

const PANDA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/data/robots/panda.urdf"
);

fn models() -> (Model, Model) {
    let coupled = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::from(RootJoint::Fixed)
    };
    (
        Model::from_urdf_file(PANDA, RootJoint::Fixed).unwrap(),
        Model::from_urdf_file_with(PANDA, &coupled).unwrap(),
    )
}

/// The independent-model configuration equivalent to a coupled one.
fn expand(independent: &Model, coupled: &Model, qc: &[f64]) -> Vec<f64> {
    let mut q = vec![0.0; independent.nq()];
    for j in coupled.moving_joints() {
        let name = &coupled.joint(j).name;
        set_joint_q(independent, &mut q, name, &qc[coupled.joint_q_range(j)]).unwrap();
    }
    for b in coupled.bodies().iter().filter(|b| b.mimic.is_some()) {
        let name = &coupled.joint(b.joint.unwrap()).name;
        set_joint_q(independent, &mut q, name, &[b.coordinate(qc)]).unwrap();
    }
    q
}

#[test]
fn a_follower_removes_its_coordinate_and_moves_with_its_leader() {
    let (independent, coupled) = models();
    assert_eq!((independent.nq(), coupled.nq(), coupled.nv()), (9, 8, 8));
    let follower = coupled.joint(coupled.joint_index("panda_finger_joint2").unwrap());
    let mimic = follower.mimic.as_ref().unwrap();
    assert_eq!(mimic.joint, "panda_finger_joint1");
    let (mut di, mut dc) = (
        KinematicsData::new(&independent),
        KinematicsData::new(&coupled),
    );
    let mut rng = rand::rngs::SmallRng::seed_from_u64(5);
    let mut qc = vec![0.0; coupled.nq()];
    for _ in 0..20 {
        random_configuration(&coupled, &mut rng, &mut qc).unwrap();
        let qi = expand(&independent, &coupled, &qc);
        let leader = qi
            [independent.joint_q_range(independent.joint_index("panda_finger_joint1").unwrap())][0];
        let f2 = qi
            [independent.joint_q_range(independent.joint_index("panda_finger_joint2").unwrap())][0];
        assert!((f2 - (mimic.multiplier * leader + mimic.offset)).abs() < 1e-15);
        forward_kinematics(&independent, &mut di, &qi).unwrap();
        forward_kinematics(&coupled, &mut dc, &qc).unwrap();
        for (a, b) in di.world_from_link().iter().zip(dc.world_from_link()) {
            assert!(a.abs_diff_eq(b, 1e-15, 1e-15));
        }
    }
    let mut q = vec![0.0; coupled.nq()];
    assert!(matches!(
        set_joint_q(&coupled, &mut q, "panda_finger_joint2", &[0.01]),
        Err(KinematicsError::InvalidJointValue { .. })
    ));
}

#[test]
fn coupled_jacobians_equal_finite_differences() {
    let (_, model) = models();
    let mut data = KinematicsData::new(&model);
    let mut rng = rand::rngs::SmallRng::seed_from_u64(9);
    let mut q = vec![0.0; model.nq()];
    random_configuration(&model, &mut rng, &mut q).unwrap();
    let v: Vec<f64> = (0..model.nv()).map(|k| 0.3 - 0.1 * k as f64).collect();
    let (mut jac, mut direct) = (
        vec![Motion::ZERO; model.nv()],
        vec![Motion::ZERO; model.nv()],
    );
    let (mut dj, mut jp, mut jm) = (jac.clone(), jac.clone(), jac.clone());
    let eps = 1e-6;
    for link in ["panda_rightfinger", "panda_leftfinger", "panda_hand_tcp"] {
        let frame = FrameId::find(&model, link).unwrap();
        for rf in [
            ReferenceFrame::World,
            ReferenceFrame::Local,
            ReferenceFrame::LocalWorldAligned,
        ] {
            compute_joint_jacobians(&model, &mut data, &q).unwrap();
            frame_jacobian(&model, &data, frame, rf, &mut jac).unwrap();
            compute_frame_jacobian(&model, &mut data, &q, frame, rf, &mut direct).unwrap();
            let t0 = *data.world_from(frame).unwrap();
            for k in 0..model.nv() {
                assert!(jac[k].abs_diff_eq(&direct[k], 1e-14));
                let mut dv = vec![0.0; model.nv()];
                dv[k] = eps;
                let mut qp = vec![0.0; model.nq()];
                integrate(&model, &q, &dv, &mut qp).unwrap();
                forward_kinematics(&model, &mut data, &qp).unwrap();
                let local =
                    explog::log6(&t0.inv_mul(data.world_from(frame).unwrap())) * (1.0 / eps);
                let fd = change_reference(&t0, &local, rf);
                assert!(
                    fd.abs_diff_eq(&jac[k], 1e-5),
                    "{link} {rf:?} column {k}: {fd:?} vs {:?}",
                    jac[k]
                );
            }
            // dJ/dt along v by central differences.
            let mut qp = vec![0.0; model.nq()];
            let mut qm = vec![0.0; model.nq()];
            integrate(
                &model,
                &q,
                &v.iter().map(|x| x * eps).collect::<Vec<_>>(),
                &mut qp,
            )
            .unwrap();
            integrate(
                &model,
                &q,
                &v.iter().map(|x| -x * eps).collect::<Vec<_>>(),
                &mut qm,
            )
            .unwrap();
            compute_joint_jacobians(&model, &mut data, &qp).unwrap();
            frame_jacobian(&model, &data, frame, rf, &mut jp).unwrap();
            compute_joint_jacobians(&model, &mut data, &qm).unwrap();
            frame_jacobian(&model, &data, frame, rf, &mut jm).unwrap();
            compute_joint_jacobians_time_variation(&model, &mut data, &q, &v).unwrap();
            frame_jacobian_time_variation(&model, &data, frame, rf, &mut dj).unwrap();
            for k in 0..model.nv() {
                let fd = (jp[k] - jm[k]) * (0.5 / eps);
                assert!(fd.abs_diff_eq(&dj[k], 1e-7), "{link} {rf:?} dJ column {k}");
            }
        }
    }
}

#[test]
fn a_dangling_mimic_is_an_error_when_coupled() {
    let urdf = r#"<robot name="r"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="nowhere"/></joint></robot>"#;
    // Independent (default): dropped with a warning.
    let m = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap();
    assert!(
        matches!(&m.warnings()[0], Issue::UnknownMimicTarget { target, .. } if target == "nowhere")
    );
    let coupled = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::default()
    };
    let err = Model::from_urdf_str_with(urdf, &coupled).unwrap_err();
    assert!(matches!(&err, ModelError::Invalid { issues, .. }
        if matches!(&issues[0], Issue::UnknownMimicTarget { joint, target } if joint == "j" && target == "nowhere")));
}
