//! Tree queries and the printed tree, on panda and on the samples.

use kinetree_model::{Model, RootJoint, samples};

fn panda(root: RootJoint) -> Model {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    Model::from_urdf_file(path, root).unwrap()
}

fn names(model: &Model, links: impl IntoIterator<Item = usize>) -> Vec<&str> {
    links
        .into_iter()
        .map(|l| model.link(l).name.as_str())
        .collect()
}

#[test]
fn panda_tree_queries() {
    for root in [RootJoint::Fixed, RootJoint::Floating] {
        let m = panda(root);
        let l = |n: &str| m.link_index(n).unwrap();
        assert_eq!(m.root_link(), Some(l("panda_link0")));
        assert_eq!(
            names(&m, m.children(l("panda_hand"))),
            ["panda_hand_tcp", "panda_leftfinger", "panda_rightfinger"]
        );
        assert_eq!(names(&m, m.children(l("panda_link3"))), ["panda_link4"]);
        assert!(m.children(l("panda_leftfinger")).next().is_none());
        assert_eq!(
            names(&m, m.descendants(l("panda_link7"))),
            [
                "panda_link8",
                "panda_hand",
                "panda_hand_tcp",
                "panda_leftfinger",
                "panda_rightfinger"
            ]
        );
        assert_eq!(m.descendants(l("panda_link0")).len(), m.links().len() - 1);
        assert!(m.descendants(l("panda_rightfinger")).is_empty());
        assert_eq!(
            names(&m, m.path_to_root(l("panda_leftfinger"))),
            [
                "panda_leftfinger",
                "panda_hand",
                "panda_link8",
                "panda_link7",
                "panda_link6",
                "panda_link5",
                "panda_link4",
                "panda_link3",
                "panda_link2",
                "panda_link1",
                "panda_link0"
            ]
        );
        assert_eq!(names(&m, m.path_to_root(l("panda_link0"))), ["panda_link0"]);
        let ca = |a: &str, b: &str| m.link(m.common_ancestor(l(a), l(b)).unwrap()).name.clone();
        assert_eq!(ca("panda_leftfinger", "panda_rightfinger"), "panda_hand");
        assert_eq!(ca("panda_hand_tcp", "panda_link3"), "panda_link3");
        assert_eq!(ca("panda_link3", "panda_hand_tcp"), "panda_link3");
        assert_eq!(ca("panda_link5", "panda_link5"), "panda_link5");
        assert_eq!(ca("panda_link0", "panda_rightfinger"), "panda_link0");
        assert!(m.is_ancestor(l("panda_link2"), l("panda_hand")));
        assert!(!m.is_ancestor(l("panda_leftfinger"), l("panda_rightfinger")));
        // Fixed joints are merged: the hand and its tcp ride on joint 7's body.
        let hand_joint = m.parent_joint(l("panda_hand")).unwrap();
        assert_eq!(m.joint(hand_joint).name, "panda_hand_joint");
        assert_eq!(
            m.link_body(l("panda_hand_tcp")).0,
            m.link_body(l("panda_link7")).0
        );
        assert_eq!(m.parent_link(l("panda_link0")), None);
        match root {
            RootJoint::Fixed => assert_eq!(m.parent_joint(l("panda_link0")), None),
            RootJoint::Floating => {
                assert_eq!(
                    m.joint(m.parent_joint(l("panda_link0")).unwrap()).name,
                    "root_joint"
                );
            }
        }
    }
}

#[test]
fn branches_are_contiguous_in_depth_first_order() {
    let h = samples::humanoid_like();
    let l = |n: &str| h.link_index(n).unwrap();
    let leg = h.descendants(l("l_hip"));
    assert_eq!(
        names(&h, leg.iter().copied()),
        [
            "l_hip_roll_link",
            "l_thigh",
            "l_shin",
            "l_ankle",
            "l_foot",
            "l_sole"
        ]
    );
    assert_eq!(
        h.link(h.common_ancestor(l("l_sole"), l("r_hand")).unwrap())
            .name,
        "pelvis"
    );
}

#[test]
fn the_tree_prints_one_link_per_line() {
    let expected = "\
panda (nq = 9, nv = 9)
  panda_link0
    panda_link1 <- panda_joint1 (revolute)
      panda_link2 <- panda_joint2 (revolute)
        panda_link3 <- panda_joint3 (revolute)
          panda_link4 <- panda_joint4 (revolute)
            panda_link5 <- panda_joint5 (revolute)
              panda_link6 <- panda_joint6 (revolute)
                panda_link7 <- panda_joint7 (revolute)
                  panda_link8 <- panda_joint8 (fixed)
                    panda_hand <- panda_hand_joint (fixed)
                      panda_hand_tcp <- panda_hand_tcp_joint (fixed)
                      panda_leftfinger <- panda_finger_joint1 (prismatic)
                      panda_rightfinger <- panda_finger_joint2 (prismatic)
";
    assert_eq!(panda(RootJoint::Fixed).to_string(), expected);
    let floating = panda(RootJoint::Floating).to_string();
    assert!(
        floating.starts_with("panda (nq = 16, nv = 15)\n  panda_link0 <- root_joint (floating)\n"),
        "{floating}"
    );
    assert_eq!(
        samples::pendulum().to_string(),
        "pendulum (nq = 1, nv = 1)\n  base\n    bob <- hinge (revolute)\n"
    );
}
