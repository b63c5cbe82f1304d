//! A [`FrameId`] the model does not have is a typed error, never a panic (the kinematics layer's
//! `frame_id` test covers its own functions).

use kinetree_workspace::kinematics::model::samples;
use kinetree_workspace::kinematics::{FrameId, KinematicsError};
use kinetree_workspace::{ReachableError, ReachableParams, sample_reachable};

#[test]
fn out_of_range_frame_ids_are_errors() {
    let model = samples::planar_2r(0.3, 0.2);
    for bad in [FrameId::Link(10_000), FrameId::Frame(10_000)] {
        let (what, index) = match bad {
            FrameId::Link(l) => ("link", l),
            FrameId::Frame(f) => ("frame", f),
        };
        match sample_reachable(&model, bad, &ReachableParams::grid(3)) {
            Err(ReachableError::Kinematics(KinematicsError::FrameOutOfRange {
                what: w,
                index: i,
                ..
            })) => assert_eq!((w, i), (what, index)),
            other => panic!("{bad:?}: expected FrameOutOfRange, got {:?}", other.err()),
        }
    }
}
