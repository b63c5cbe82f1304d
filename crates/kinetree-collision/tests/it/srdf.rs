//! SRDF import and the "never in collision" proposal tool.

use crate::common::{panda, urdf};
use kinetree_collision::srdf::{parse_disabled_pairs, write_disabled_pairs};
use kinetree_collision::{
    CollisionError, CollisionModel, CollisionOptions, DisableReason, PairSampling,
    propose_disabled_pairs,
};

#[test]
fn srdf_disable_collisions_removes_link_pairs() {
    let (_, model) = panda();
    let mut cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let before = cmodel.pairs().len();
    let srdf = r#"<?xml version="1.0"?>
<robot name="panda">
  <group name="arm"><chain base_link="panda_link0" tip_link="panda_link8"/></group>
  <disable_collisions link1="panda_link0" link2="panda_link2" reason="Never"/>
  <disable_collisions link1="panda_link3" link2="panda_link1" reason="Never"></disable_collisions>
  <!-- adjacent: no candidate pair, removes nothing -->
  <disable_collisions link1="panda_link0" link2="panda_link1" reason="Adjacent"/>
</robot>"#;
    let removed = cmodel.disable_pairs_from_srdf_str(&model, srdf).unwrap();
    // link0 and link2 have 3 shapes each; link1 and link3 too.
    assert_eq!(removed, 18);
    assert_eq!(cmodel.pairs().len(), before - 18);
    let names: Vec<_> = cmodel
        .link_pairs()
        .iter()
        .map(|lp| {
            (
                model.link(lp.link_a).name.as_str(),
                model.link(lp.link_b).name.as_str(),
            )
        })
        .collect();
    assert!(!names.contains(&("panda_link0", "panda_link2")));
    assert!(!names.contains(&("panda_link1", "panda_link3")));
    // Unknown links are errors and change nothing.
    let bad = r#"<robot name="p"><disable_collisions link1="panda_link0" link2="nope"/></robot>"#;
    assert!(matches!(
        cmodel.disable_pairs_from_srdf_str(&model, bad),
        Err(CollisionError::UnknownLink { name }) if name == "nope"
    ));
    assert_eq!(cmodel.pairs().len(), before - 18);
    // Malformed XML and missing attributes are errors.
    assert!(matches!(
        parse_disabled_pairs("<robot><disable_collisions link1=\"a\"/></robot>"),
        Err(CollisionError::Srdf { .. })
    ));
    assert!(matches!(
        parse_disabled_pairs("<robot><a></b></robot>"),
        Err(CollisionError::Srdf { .. })
    ));
    // Nesting is limited as in every XML reader: the deepest accepted, then one more.
    let nested = |depth: usize| {
        format!(
            "{}<disable_collisions link1=\"a\" link2=\"b\"/>{}",
            "<g>".repeat(depth),
            "</g>".repeat(depth)
        )
    };
    let limit = kinetree_collision::kinematics::model::MAX_XML_DEPTH;
    assert_eq!(parse_disabled_pairs(&nested(limit)).unwrap().len(), 1);
    for depth in [limit + 1, 20_000] {
        let e = parse_disabled_pairs(&nested(depth)).unwrap_err();
        assert!(
            matches!(&e, CollisionError::Srdf { message, .. } if message.contains("nested deeper than 500")),
            "{e}"
        );
    }
    // Options take disabled pairs too; written entries parse back.
    let pairs = parse_disabled_pairs(srdf).unwrap();
    assert_eq!(
        parse_disabled_pairs(&format!("<robot>{}</robot>", write_disabled_pairs(&pairs))).unwrap(),
        pairs
    );
    let options = CollisionOptions {
        disabled_link_pairs: pairs
            .iter()
            .map(|p| (p.link1.clone(), p.link2.clone()))
            .collect(),
        ..CollisionOptions::default()
    };
    assert_eq!(
        CollisionModel::from_model(&model, &options)
            .unwrap()
            .pairs()
            .len(),
        before - 18
    );
}

#[test]
fn sampling_proposes_never_default_and_always_pairs() {
    // Three sibling links on prismatic joints along x (range ±0.1): `far` never reaches the
    // others, `twin` always overlaps `base_ball` (same place, big spheres), `near` sometimes hits.
    let joint = |name: &str, child: &str, x: f64| {
        format!(
            r#"<joint name="{name}" type="prismatic"><parent link="root"/><child link="{child}"/>
               <origin xyz="{x} 0 0"/><axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>"#
        )
    };
    let ball =
        |r: f64| format!("<collision><geometry><sphere radius=\"{r}\"/></geometry></collision>");
    let model = urdf(&format!(
        r#"<link name="root"/><link name="a">{}</link><link name="twin">{}</link><link name="near">{}</link><link name="far">{}</link>{}{}{}{}"#,
        ball(0.5),
        ball(0.5),
        ball(0.1),
        ball(0.1),
        joint("ja", "a", 0.0),
        joint("jt", "twin", 0.0),
        joint("jn", "near", 0.65),
        joint("jf", "far", 5.0)
    ));
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let proposals = propose_disabled_pairs(
        &model,
        &cmodel,
        &PairSampling {
            samples: 300,
            seed: 7,
            ..PairSampling::default()
        },
    )
    .unwrap();
    let reason = |a: &str, b: &str| {
        proposals.iter().find_map(|p| {
            let (x, y) = (
                model.link(p.link_a).name.as_str(),
                model.link(p.link_b).name.as_str(),
            );
            ((x, y) == (a, b) || (y, x) == (a, b)).then_some(p.reason)
        })
    };
    assert_eq!(reason("a", "twin"), Some(DisableReason::Default));
    assert_eq!(reason("a", "far"), Some(DisableReason::Never));
    assert_eq!(reason("near", "far"), Some(DisableReason::Never));
    // `near` (at 0.65 ± 0.1, radius 0.1) touches `a` (0 ± 0.1, radius 0.5) only when within 0.6.
    assert_eq!(reason("a", "near"), None);
    let srdf = write_disabled_pairs(
        &proposals
            .iter()
            .map(|p| p.to_disabled_pair(&model))
            .collect::<Vec<_>>(),
    );
    assert!(srdf.contains(r#"reason="Never""#));
}
