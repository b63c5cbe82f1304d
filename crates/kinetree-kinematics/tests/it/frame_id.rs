//! Every public function taking a [`FrameId`] returns [`KinematicsError::FrameOutOfRange`] for a
//! link or frame index the model does not have, never a panic.

use kinetree_kinematics::configuration::neutral_configuration;
use kinetree_kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree_kinematics::model::samples;
use kinetree_kinematics::spatial::{Motion, Se3};
use kinetree_kinematics::{
    Chain, FrameId, KinematicsData, KinematicsError, ReferenceFrame, compute_frame_jacobian,
    compute_joint_jacobians, compute_joint_jacobians_time_variation,
    forward_kinematics_with_velocity, frame_jacobian, frame_jacobian_time_variation,
    frame_velocity, relative_transform,
};

const BAD: [FrameId; 2] = [FrameId::Link(10_000), FrameId::Frame(10_000)];

fn out_of_range<T: std::fmt::Debug>(result: Result<T, KinematicsError>, frame: FrameId) {
    let (what, index) = match frame {
        FrameId::Link(l) => ("link", l),
        FrameId::Frame(f) => ("frame", f),
    };
    match result {
        Err(KinematicsError::FrameOutOfRange {
            what: w, index: i, ..
        }) => assert_eq!((w, i), (what, index)),
        other => panic!("{frame:?}: expected FrameOutOfRange, got {other:?}"),
    }
}

#[test]
fn out_of_range_frame_ids_are_errors() {
    let model = samples::planar_2r(0.3, 0.2);
    let q = neutral_configuration(&model);
    let v = vec![0.1; model.nv()];
    let mut data = KinematicsData::new(&model);
    let mut out = vec![Motion::ZERO; model.nv()];
    let good = FrameId::Link(model.links().len() - 1);
    let rf = ReferenceFrame::LocalWorldAligned;
    for bad in BAD {
        out_of_range(bad.check(&model), bad);
        out_of_range(bad.body(&model), bad);
        out_of_range(bad.name(&model), bad);

        forward_kinematics_with_velocity(&model, &mut data, &q, &v).unwrap();
        out_of_range(data.world_from(bad), bad);
        out_of_range(relative_transform(&data, good, bad), bad);
        out_of_range(relative_transform(&data, bad, good), bad);
        out_of_range(frame_velocity(&model, &data, bad, rf), bad);

        compute_joint_jacobians(&model, &mut data, &q).unwrap();
        out_of_range(frame_jacobian(&model, &data, bad, rf, &mut out), bad);
        out_of_range(
            compute_frame_jacobian(&model, &mut data, &q, bad, rf, &mut out),
            bad,
        );
        compute_joint_jacobians_time_variation(&model, &mut data, &q, &v).unwrap();
        out_of_range(
            frame_jacobian_time_variation(&model, &data, bad, rf, &mut out),
            bad,
        );

        let mut chain = Chain::new(model.clone());
        out_of_range(chain.world_from_id(bad), bad);

        let mut solver = IkSolver::new(&model, IkParams::default());
        let target = IkTarget::new(bad, Se3::IDENTITY);
        out_of_range(
            solver
                .solve(&model, &mut data, &target, &q)
                .map(|r| r.q.to_vec()),
            bad,
        );
    }
    // The good id still works everywhere (the checks do not reject valid ids).
    assert!(good.check(&model).is_ok());
    assert!(data.world_from(good).is_ok());
}

#[test]
fn a_frame_name_two_links_share_is_ambiguous_and_lists_the_choices() {
    use kinetree_kinematics::model::Model;
    // Two parts with a frame MOUNT each (as a yapCAD assembly has), and one unique frame.
    let model = Model::from_json_str(
        r#"{"name": "two", "links": [{"name": "a"}, {"name": "b"}],
            "joints": [{"name": "ab", "type": "revolute", "parent": "a", "child": "b",
                        "axis": [0, 0, 1], "limits": {"lower": -1, "upper": 1}}],
            "frames": [{"name": "MOUNT", "link": "a", "origin": {"xyz": [0, 0, 0.1]}},
                       {"name": "MOUNT", "link": "b", "origin": {"xyz": [0, 0, 0.2]}},
                       {"name": "TIP", "link": "b", "origin": {"xyz": [1, 0, 0]}}]}"#,
        None,
    )
    .unwrap();
    let m = &model;
    let e = FrameId::find(m, "MOUNT").unwrap_err();
    match &e {
        KinematicsError::AmbiguousFrame { name, candidates } => {
            assert_eq!(name, "MOUNT");
            assert_eq!(candidates, &["a/MOUNT", "b/MOUNT"]);
        }
        other => panic!("expected AmbiguousFrame, got {other:?}"),
    }
    assert!(
        e.to_string().contains("give one of a/MOUNT, b/MOUNT"),
        "{e}"
    );
    // Each is reachable in full, and the unique frame by its bare name.
    let a = FrameId::find(m, "a/MOUNT").unwrap();
    let b = FrameId::find(m, "b/MOUNT").unwrap();
    assert_ne!(a, b);
    assert_eq!(
        FrameId::find(m, "TIP").unwrap(),
        FrameId::find(m, "b/TIP").unwrap()
    );
    assert!(matches!(
        FrameId::find(m, "NOWHERE"),
        Err(KinematicsError::UnknownFrame { .. })
    ));
}
