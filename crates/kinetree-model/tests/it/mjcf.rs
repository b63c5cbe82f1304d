//! The MJCF loader on documents written by hand, one feature per test, with the expected values
//! worked out by hand (the comparison with MuJoCo itself is in the dynamics tests).

use kinetree_model::spatial::glam::{DMat3, DVec3};
use kinetree_model::spatial::{Se3, Symmetric3};
use kinetree_model::{Geometry, JointKind, Model, ModelError};
use std::f64::consts::{FRAC_PI_2, PI};

fn load(xml: &str) -> Model {
    Model::from_mjcf_str(xml).unwrap_or_else(|e| panic!("{e}"))
}

fn err(xml: &str) -> String {
    match Model::from_mjcf_str(xml) {
        Ok(_) => panic!("loaded: {xml}"),
        Err(e) => e.to_string(),
    }
}

fn close_se3(a: &Se3, b: &Se3) -> bool {
    a.abs_diff_eq(b, 1e-12, 1e-12)
}

fn joint<'m>(m: &'m Model, name: &str) -> &'m kinetree_model::Joint {
    m.joint(
        m.joint_index(name)
            .unwrap_or_else(|| panic!("no joint {name}")),
    )
}

fn link_mass(m: &Model, name: &str) -> f64 {
    m.link(m.link_index(name).unwrap()).inertia().mass
}

fn worldbody(body: &str) -> String {
    format!("<mujoco><worldbody>{body}</worldbody></mujoco>")
}

#[test]
fn bodies_hang_from_the_world_link_in_depth_first_order() {
    let m = load(&worldbody(
        r#"<geom type="plane" size="1 1 0.1"/>
        <body name="a" pos="1 0 0"><joint name="ja"/><geom size="0.1"/>
          <body pos="0 1 0"><geom size="0.1"/></body>
        </body>
        <body name="b"><joint/><geom size="0.1"/></body>"#,
    ));
    let names: Vec<&str> = m.links().iter().map(|l| l.name.as_str()).collect();
    // World = body 0; the unnamed body is body2 (depth-first), welded by a fixed joint.
    assert_eq!(names, ["world", "a", "body2", "b"]);
    assert_eq!(joint(&m, "body2:fixed").kind, JointKind::Fixed);
    assert!(close_se3(
        &joint(&m, "body2:fixed").placement,
        &Se3::from_translation(DVec3::Y)
    ));
    // An unnamed joint is <body>:<k>; a hinge without range is continuous, about z.
    assert_eq!(joint(&m, "b:0").kind, JointKind::Continuous);
    assert_eq!(joint(&m, "ja").axis, DVec3::Z);
    assert_eq!((m.nq(), m.nv()), (2, 2));
    assert_eq!(m.root_link(), m.link_index("world"));
}

#[test]
fn includes_are_spliced_in_and_loops_refused() {
    let dir = std::env::temp_dir().join(format!("kinetree-mjcf-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(
        dir.join("parts/arm.xml"),
        r#"<mujoco><body name="arm"><joint name="shoulder" type="slide"/><geom size="0.1"/></body></mujoco>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("robot.xml"),
        r#"<mujoco><worldbody><include file="parts/arm.xml"/></worldbody></mujoco>"#,
    )
    .unwrap();
    let m = Model::from_mjcf_file(dir.join("robot.xml")).unwrap();
    assert_eq!(joint(&m, "shoulder").kind, JointKind::Prismatic);
    // A file that includes itself.
    std::fs::write(
        dir.join("loop.xml"),
        r#"<mujoco><worldbody><include file="loop.xml"/></worldbody></mujoco>"#,
    )
    .unwrap();
    let e = Model::from_mjcf_file(dir.join("loop.xml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("already included") && e.contains("line 1"),
        "{e}"
    );
    std::fs::write(
        dir.join("missing.xml"),
        "<mujoco>\n<worldbody>\n<include file=\"nothere.xml\"/></worldbody></mujoco>",
    )
    .unwrap();
    let e = Model::from_mjcf_file(dir.join("missing.xml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nothere.xml") && e.contains("line 3"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn default_classes_nest_and_childclass_applies_below() {
    let m = load(
        r#"<mujoco>
      <default>
        <joint damping="1" armature="0.5"/>
        <geom size="0.1 0.2 0.3" type="box"/>
        <default class="heavy">
          <joint damping="7"/>
          <geom density="2000"/>
          <default class="sphere"><geom type="sphere"/></default>
        </default>
      </default>
      <worldbody>
        <body name="plain"><joint name="j0"/><geom/></body>
        <body name="styled" childclass="heavy">
          <joint name="j1"/>
          <geom size="0.05"/>
          <body name="inner"><joint name="j2" class="main"/><geom class="sphere" size="0.5"/></body>
        </body>
      </worldbody>
    </mujoco>"#,
    );
    assert_eq!(joint(&m, "j0").dynamics.damping, 1.0);
    assert_eq!(joint(&m, "j0").dynamics.armature, 0.5);
    // The class's damping, its parent's armature.
    assert_eq!(joint(&m, "j1").dynamics.damping, 7.0);
    assert_eq!(joint(&m, "j1").dynamics.armature, 0.5);
    assert_eq!(joint(&m, "j2").dynamics.damping, 1.0);
    // A box of half sides 0.1, 0.2, 0.3 at 1000 kg/m³.
    assert!((link_mass(&m, "plain") - 8.0 * 0.006 * 1000.0).abs() < 1e-9);
    // size="0.05" replaces only the first half side: 0.05 × 0.2 × 0.3 at 2000 kg/m³.
    assert!((link_mass(&m, "styled") - 8.0 * 0.003 * 2000.0).abs() < 1e-9);
    // A sphere of radius 0.5 at the heavy density.
    let sphere = 4.0 / 3.0 * PI * 0.125 * 2000.0;
    assert!((link_mass(&m, "inner") - sphere).abs() < 1e-9);
    let e = err(&worldbody(r#"<body><geom class="nope" size="1"/></body>"#));
    assert!(e.contains("unknown default class 'nope'"), "{e}");
}

#[test]
fn every_orientation_form_and_the_compiler_angle() {
    let quarter = Se3::from_rotation_z(FRAC_PI_2);
    for attrs in [
        r#"quat="1 0 0 1""#,
        r#"axisangle="0 0 1 90""#,
        r#"euler="0 0 90""#,
        r#"xyaxes="0 1 0 -1 0 0""#,
    ] {
        let m = load(&worldbody(&format!(r#"<body name="b" {attrs}/>"#)));
        assert!(
            close_se3(&joint(&m, "b:fixed").placement, &quarter),
            "{attrs}"
        );
    }
    let m = load(
        r#"<mujoco><compiler angle="radian" eulerseq="XYZ"/><worldbody>
        <body name="b" euler="1.5707963267948966 0 0"/>
        <body name="z" zaxis="1 0 0"/></worldbody></mujoco>"#,
    );
    assert!(close_se3(
        &joint(&m, "b:fixed").placement,
        &Se3::from_rotation_x(FRAC_PI_2)
    ));
    // zaxis: the shortest arc from z to x is a quarter turn about y.
    assert!(close_se3(
        &joint(&m, "z:fixed").placement,
        &Se3::from_rotation_y(FRAC_PI_2)
    ));
    let e = err(&worldbody(r#"<body quat="1 0 0 0" euler="0 0 1"/>"#));
    assert!(e.contains("several orientations"), "{e}");
}

#[test]
fn frames_move_what_they_hold() {
    let m = load(&worldbody(
        r#"<body name="b"><geom size="0.1"/>
          <frame pos="1 0 0" euler="0 0 90">
            <joint name="j" type="slide" axis="1 0 0" pos="0 1 0"/>
            <site name="s" pos="1 0 0"/>
            <frame pos="0 0 2"><body name="c"/></frame>
          </frame>
        </body>"#,
    ));
    // The slide axis x turned a quarter about z is y; its anchor (0, 1, 0) lands at (0, 0, 0).
    let j = joint(&m, "j");
    assert!((j.axis - DVec3::Y).length() < 1e-12);
    let s = &m.frames()[m.frame_index("s").unwrap()];
    assert!((s.placement.translation - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12);
    let c = joint(&m, "c:fixed").placement;
    assert!((c.translation - DVec3::new(1.0, 0.0, 2.0)).length() < 1e-12);
    assert!(close_se3(
        &Se3::from_rotation(c.rotation),
        &Se3::from_rotation_z(FRAC_PI_2)
    ));
}

#[test]
fn explicit_inertials_diagonal_and_full() {
    let m = load(&worldbody(
        r#"<body name="d"><inertial pos="0.1 0 0" mass="2" diaginertia="1 2 3" euler="0 0 90"/></body>
        <body name="f"><inertial pos="0 0 0" mass="1" fullinertia="2 3 4 0.1 0.2 0.3"/></body>"#,
    ));
    let d = m.link(m.link_index("d").unwrap()).inertia();
    assert_eq!(d.mass, 2.0);
    assert!((d.com - DVec3::new(0.1, 0.0, 0.0)).length() < 1e-15);
    // Principal moments 1, 2, 3 about axes turned a quarter about z: x ↔ y.
    let expected = Symmetric3::from_diagonal(DVec3::new(2.0, 1.0, 3.0));
    for (a, b) in d.rotational.to_voigt().iter().zip(expected.to_voigt()) {
        assert!((a - b).abs() < 1e-12);
    }
    let f = m.link(m.link_index("f").unwrap()).inertia();
    let expected = Symmetric3::new(2.0, 0.1, 0.2, 3.0, 0.3, 4.0);
    for (a, b) in f.rotational.to_voigt().iter().zip(expected.to_voigt()) {
        assert!((a - b).abs() < 1e-12, "{a} {b}");
    }
}

#[test]
fn inertia_from_geoms_follows_inertiafromgeom() {
    // Two 1 kg spheres (mass given) at x = ±1: the body's centre is the middle and its inertia
    // about z is 2 · (2/5 · 0.1²) + 2 · 1².
    let two = r#"<body name="b"><geom size="0.1" pos="1 0 0" mass="1"/><geom size="0.1" pos="-1 0 0" mass="1"/>"#;
    let m = load(&worldbody(&format!("{two}</body>")));
    let i = m.link(m.link_index("b").unwrap()).inertia();
    assert_eq!(i.mass, 2.0);
    assert!(i.com.length() < 1e-15);
    assert!((i.rotational.zz - (0.008 + 2.0)).abs() < 1e-12);
    assert!((i.rotational.xx - 0.008).abs() < 1e-12);
    // auto (the default): an <inertial> wins over geoms.
    let with_inertial =
        format!(r#"{two}<inertial pos="0 0 0" mass="5" diaginertia="1 1 1"/></body>"#);
    assert_eq!(link_mass(&load(&worldbody(&with_inertial)), "b"), 5.0);
    // true: geoms win over the <inertial>.
    let t = format!(
        r#"<mujoco><compiler inertiafromgeom="true"/><worldbody>{with_inertial}</worldbody></mujoco>"#
    );
    assert_eq!(link_mass(&load(&t), "b"), 2.0);
    // false: geoms never count.
    let f = format!(
        r#"<mujoco><compiler inertiafromgeom="false"/><worldbody>{two}</body></worldbody></mujoco>"#
    );
    assert_eq!(link_mass(&load(&f), "b"), 0.0);
    // Geoms outside inertiagrouprange do not count; density 0 weighs nothing.
    let g = r#"<mujoco><compiler inertiagrouprange="0 2"/><worldbody><body name="b">
        <geom size="0.1" group="3"/><geom size="0.1" density="0"/></body></worldbody></mujoco>"#;
    assert_eq!(link_mass(&load(g), "b"), 0.0);
    // A capsule from fromto: radius 0.1, cylinder length 2 along x, at (1, 0, 0).
    let m = load(&worldbody(
        r#"<body name="c"><geom type="capsule" fromto="0 0 0 2 0 0" size="0.1"/></body>"#,
    ));
    let c = m.link(m.link_index("c").unwrap());
    let volume = PI * 0.01 * 2.0 + 4.0 / 3.0 * PI * 0.001;
    assert!((c.inertia().mass - 1000.0 * volume).abs() < 1e-9);
    assert!((c.inertia().com - DVec3::X).length() < 1e-15);
    assert_eq!(
        c.collisions[0].geometry,
        Geometry::Capsule {
            radius: 0.1,
            length: 2.0
        }
    );
    // The capsule's axis (its frame's z) lies along x.
    let z = c.collisions[0].origin.rotation * DVec3::Z;
    assert!((z.abs() - DVec3::X).length() < 1e-12);
}

#[test]
fn bound_and_total_mass() {
    let m = load(
        r#"<mujoco><compiler boundmass="0.5" boundinertia="0.01"/><worldbody>
        <body name="light"><joint/></body></worldbody></mujoco>"#,
    );
    let i = m.link(m.link_index("light").unwrap()).inertia();
    assert_eq!(i.mass, 0.5);
    assert_eq!(i.rotational.xx, 0.01);
    let m = load(
        r#"<mujoco><compiler settotalmass="10"/><worldbody>
        <body name="a"><geom size="0.1" mass="1"/></body>
        <body name="b"><geom size="0.1" mass="3"/></body></worldbody></mujoco>"#,
    );
    assert!((link_mass(&m, "a") - 2.5).abs() < 1e-12);
    assert!((link_mass(&m, "b") - 7.5).abs() < 1e-12);
}

#[test]
fn hinge_and_slide_refs_fold_into_the_placement() {
    let m = load(&worldbody(
        r#"<body name="h"><joint name="hinge" axis="0 0 1" ref="90" range="0 180"/><geom size="1"/></body>
        <body name="s"><joint name="slide" type="slide" axis="0 0 2" ref="0.5"/><geom size="1"/></body>"#,
    ));
    // At q = ref the body is where the file puts it: placement · R(ref) = identity.
    let h = joint(&m, "hinge");
    assert!(close_se3(
        &(h.placement * Se3::from_rotation_z(FRAC_PI_2)),
        &Se3::IDENTITY
    ));
    assert_eq!(h.kind, JointKind::Revolute);
    // Limits stay as written (degrees → radians), in qpos units.
    assert!((h.limits.lower - 0.0).abs() < 1e-15 && (h.limits.upper - PI).abs() < 1e-15);
    let s = joint(&m, "slide");
    assert!(close_se3(
        &s.placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, -0.5))
    ));
    assert_eq!(s.axis, DVec3::Z);
}

#[test]
fn several_joints_in_a_body_chain_through_their_anchors() {
    let m = load(&worldbody(
        r#"<body name="torso" pos="0 0 1">
          <joint name="x" type="slide" axis="1 0 0" pos="0 0 -1"/>
          <joint name="pitch" axis="0 1 0" pos="0 0 0.5"/>
          <geom size="0.1"/>
        </body>"#,
    ));
    // torso:0 carries the slide, torso:1 sits at the hinge's anchor, and a fixed joint brings
    // the anchor back to the body origin.
    let names: Vec<&str> = m.links().iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["world", "torso:0", "torso:1", "torso"]);
    assert!(close_se3(
        &joint(&m, "x").placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, 0.0))
    ));
    assert!(close_se3(
        &joint(&m, "pitch").placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, 1.5))
    ));
    assert!(close_se3(
        &joint(&m, "torso:anchor").placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, -0.5))
    ));
    assert_eq!(
        m.link_index("torso:1").map(|l| m.parent_joint(l)),
        Some(m.joint_index("pitch"))
    );
}

#[test]
fn ball_and_free_joints_and_their_coordinates() {
    let m = load(&worldbody(
        r#"<body name="base" pos="1 2 3"><freejoint name="root"/><geom size="0.1"/>
          <body name="arm"><joint name="ball" type="ball" pos="0 0 0.2"/><geom size="0.1"/></body>
        </body>"#,
    ));
    assert_eq!(joint(&m, "root").kind, JointKind::Floating);
    // A free joint overwrites the body pose: its placement is the identity in the world.
    assert!(close_se3(&joint(&m, "root").placement, &Se3::IDENTITY));
    assert_eq!(joint(&m, "ball").kind, JointKind::Spherical);
    assert_eq!((m.nq(), m.nv()), (11, 9));
    let qpos = [1.0, 2.0, 3.0, 0.5, 0.5, 0.5, 0.5, 0.0, 1.0, 0.0, 0.0];
    let q = m.q_from_mujoco(&qpos).unwrap();
    assert_eq!(q, [1.0, 2.0, 3.0, 0.5, 0.5, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0]);
    assert_eq!(m.q_to_mujoco(&q).unwrap(), qpos);
    // The rotation of qpos[3..7] takes x to y, y to z, z to x: a world velocity along x is
    // along the body's z; the ball joint's velocity is untouched.
    let qvel = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 7.0, 8.0, 9.0];
    let v = m.v_from_mujoco(&qpos, &qvel).unwrap();
    for (a, b) in v.iter().zip([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 7.0, 8.0, 9.0]) {
        assert!((a - b).abs() < 1e-12, "{v:?}");
    }
    let e = err(&worldbody(
        r#"<body><body><freejoint/><geom size="1"/></body></body>"#,
    ));
    assert!(e.contains("free joint"), "{e}");
    assert!(matches!(
        m.v_from_mujoco(&qpos, &[0.0; 3]),
        Err(ModelError::Length { what: "qvel", .. })
    ));
}

#[test]
fn limits_follow_limited_and_autolimits() {
    let m = load(&worldbody(
        r#"<body><joint name="auto" range="-10 10"/><joint name="off" limited="false" range="-1 1"/>
        <joint name="slide" type="slide" range="-0.5 0.5"/><geom size="1"/></body>"#,
    ));
    assert_eq!(joint(&m, "auto").kind, JointKind::Revolute);
    assert!((joint(&m, "auto").limits.upper - 10f64.to_radians()).abs() < 1e-15);
    assert_eq!(joint(&m, "off").kind, JointKind::Continuous);
    // Slide ranges are lengths: never converted.
    assert_eq!(joint(&m, "slide").limits.lower, -0.5);
    let e = err(
        r#"<mujoco><compiler autolimits="false"/><worldbody><body><joint range="0 1"/></body></worldbody></mujoco>"#,
    );
    assert!(e.contains("'limited' is not"), "{e}");
    let e = err(&worldbody(
        r#"<body><joint range="1 0"/><geom size="1"/></body>"#,
    ));
    assert!(e.contains("range[0] must be smaller"), "{e}");
}

#[test]
fn joint_dynamics_sites_geoms_and_gravity() {
    let m = load(
        r#"<mujoco><option gravity="0 0 -3"/><worldbody>
        <site name="origin"/>
        <body name="b"><joint name="j" damping="0.3" frictionloss="0.2" armature="0.1"/>
          <geom name="solid" size="0.1"/>
          <geom name="ghost" size="0.1" contype="0" conaffinity="0"/>
          <site pos="0 0 1"/>
        </body></worldbody></mujoco>"#,
    );
    let d = joint(&m, "j").dynamics;
    assert_eq!((d.damping, d.friction, d.armature), (0.3, 0.2, 0.1));
    assert_eq!(m.gravity(), DVec3::new(0.0, 0.0, -3.0));
    let b = m.link(m.link_index("b").unwrap());
    assert_eq!(b.visuals.len(), 2);
    let colliding: Vec<_> = b.collisions.iter().map(|c| c.name.as_deref()).collect();
    assert_eq!(colliding, [Some("solid")]);
    // Sites are frames; the unnamed one is site1 (world's site is site0).
    assert!(m.frame_index("origin").is_some());
    let s = &m.frames()[m.frame_index("site1").unwrap()];
    assert_eq!(s.placement.translation, DVec3::Z);
    let off = load(r#"<mujoco><option><flag gravity="disable"/></option><worldbody/></mujoco>"#);
    assert_eq!(off.gravity(), DVec3::ZERO);
}

#[test]
fn what_is_not_modelled_is_counted() {
    let m = load(
        r#"<mujoco><worldbody><body><joint name="j" stiffness="5"/><geom size="0.1"/><camera/></body></worldbody>
        <actuator><motor joint="j"/><motor joint="j"/></actuator>
        <sensor><jointpos joint="j"/></sensor>
        <tendon><fixed><joint joint="j" coef="1"/></fixed></tendon></mujoco>"#,
    );
    let ignored = m.ignored().join("; ");
    for what in [
        "actuator/motor (×2)",
        "sensor/jointpos",
        "tendon/fixed",
        "camera",
        "stiffness 5",
    ] {
        assert!(ignored.contains(what), "{what} in {ignored}");
    }
}

#[test]
fn bad_documents_are_typed_errors_naming_the_line() {
    let cases = [
        ("<robot/>", "root element"),
        (
            "<mujoco><worldbody><body><bogus/></body></worldbody></mujoco>",
            "unknown element <bogus>",
        ),
        (
            "<mujoco><worldbody>\n<body pos=\"1 x 2\"/></worldbody></mujoco>",
            "line 2",
        ),
        (
            "<mujoco><worldbody><body pos=\"1 nan 2\"/></worldbody></mujoco>",
            "not a finite number",
        ),
        (
            "<mujoco><worldbody><body><geom type=\"box\" size=\"1 1\"/></body></worldbody></mujoco>",
            "positive size",
        ),
        (
            "<mujoco><worldbody><body><joint type=\"twist\"/></body></worldbody></mujoco>",
            "unknown joint type",
        ),
        (
            "<mujoco><worldbody><body name=\"m\"><joint/><body><joint/><geom size=\"1\"/></body></body></worldbody></mujoco>",
            "body 'm' has joints but no mass",
        ),
        (
            "<mujoco><worldbody><replicate count=\"2\"/></worldbody></mujoco>",
            "not supported yet",
        ),
        (
            "<mujoco><worldbody><body name=\"a\"/><body name=\"a\"/></worldbody></mujoco>",
            "a",
        ),
        (
            "<mujoco><worldbody><body><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 3\"/></body></worldbody></mujoco>",
            "A + B >= C",
        ),
        (
            "<mujoco><compiler coordinate=\"global\"/></mujoco>",
            "global coordinates",
        ),
    ];
    for (xml, needle) in cases {
        let e = err(xml);
        assert!(e.contains(needle), "{needle} in {e}");
    }
    let deep = format!(
        "<mujoco><worldbody>{}{}</worldbody></mujoco>",
        "<body>".repeat(600),
        "</body>".repeat(600)
    );
    assert!(err(&deep).contains("nested deeper"));
    // balanceinertia repairs what MuJoCo would refuse.
    let m = load(
        r#"<mujoco><compiler balanceinertia="true"/><worldbody><body name="b"><inertial pos="0 0 0" mass="1" diaginertia="1 1 3"/></body></worldbody></mujoco>"#,
    );
    let i = m.link(m.link_index("b").unwrap()).inertia().rotational;
    assert!((i.xx - 5.0 / 3.0).abs() < 1e-12 && (i.zz - 5.0 / 3.0).abs() < 1e-12);
    // A moving body without mass is fine when a welded child carries some (MuJoCo's rule).
    load(&worldbody(
        r#"<body><joint/><body><geom size="1"/></body></body>"#,
    ));
    let _ = DMat3::IDENTITY;
}

#[test]
fn from_file_tells_mjcf_by_its_root() {
    let dir = std::env::temp_dir().join(format!("kinetree-mjcf-detect-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("robot.model");
    std::fs::write(
        &path,
        "<?xml version=\"1.0\"?>\n<mujoco model=\"m\"><worldbody><body><joint/><geom size=\"1\"/></body></worldbody></mujoco>",
    )
    .unwrap();
    let m = Model::from_file(&path, None).unwrap();
    assert_eq!((m.name(), m.nq()), ("m", 1));
    let hopper = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/mjcf/models/gym_hopper/hopper.xml"
    );
    assert_eq!(Model::from_file(hopper, None).unwrap().name(), "hopper");
    let xml = dir.join("robot.xml");
    std::fs::copy(&path, &xml).unwrap();
    assert_eq!(Model::from_file(&xml, None).unwrap().nq(), 1);
    assert!(matches!(
        Model::from_file(&xml, kinetree_model::RootJoint::Floating),
        Err(ModelError::Unsupported { format: "MJCF", .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn models_are_written_as_mjcf() {
    use kinetree_model::{JointLimits, JointSpec, Link, ModelBuilder};
    let heavy = |name: &str| {
        Link::new(name).with_mass(
            1.0,
            DVec3::ZERO,
            Symmetric3::from_diagonal(DVec3::splat(0.1)),
        )
    };
    let mut b = ModelBuilder::new("kinds");
    b.add_link(heavy("base"))
        .add_link(heavy("slider"))
        .add_link(heavy("puck"))
        .add_joint(
            JointSpec::new("cyl", JointKind::Cylindrical, "base", "slider")
                .with_axis(DVec3::X)
                .with_limits(JointLimits::position(-1.0, 1.0))
                .with_placement(Se3::from_translation(DVec3::Z)),
        )
        .add_joint(
            JointSpec::new("plane", JointKind::Planar, "slider", "puck").with_axis(DVec3::Z),
        );
    let model = b.build().unwrap();
    let xml = model.to_mjcf_string().unwrap();
    let back = load(&xml);
    // One joint per coordinate, in the same order: q is the same.
    let names: Vec<&str> = back
        .moving_joints()
        .map(|j| back.joint(j).name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "cyl:slide",
            "cyl:hinge",
            "plane:x",
            "plane:y",
            "plane:angle"
        ]
    );
    assert_eq!(back.nq(), model.nq());
    assert_eq!(joint(&back, "cyl:hinge").limits.upper, 1.0);
    // The base is welded under the world body, the slider sits 1 m up.
    assert!(close_se3(
        &joint(&back, "cyl:slide").placement,
        &Se3::from_translation(DVec3::Z)
    ));
    assert_eq!(link_mass(&back, "puck"), 1.0);
    // MuJoCo refuses a moving body without mass: the export says which.
    let mut b = ModelBuilder::new("light");
    b.add_link(heavy("base"))
        .add_link(Link::new("ghost"))
        .add_joint(
            JointSpec::new("j", JointKind::Revolute, "base", "ghost")
                .with_limits(JointLimits::position(-1.0, 1.0)),
        );
    let e = b.build().unwrap().to_mjcf_string().unwrap_err().to_string();
    assert!(e.contains("joint 'j'") && e.contains("ghost"), "{e}");
}

#[test]
fn masses_inferred_from_meshes_match_mujoco() {
    use kinetree_model::spatial::glam::DQuat;
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/mjcf_mesh"
    );
    let model = Model::from_mjcf_file(format!("{dir}/meshes.xml")).unwrap();
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(format!("{dir}/meshes.json")).unwrap())
            .unwrap();
    let numbers = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let bodies = reference["meshes"]["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 5);
    for b in &bodies[1..] {
        let name = b["name"].as_str().unwrap();
        let ours = model.link(model.link_index(name).unwrap()).inertia();
        let mass = b["mass"].as_f64().unwrap();
        assert!(
            (ours.mass - mass).abs() <= 1e-12 * mass,
            "{name}: mass {} vs {mass}",
            ours.mass
        );
        let ipos = DVec3::from_slice(&numbers(&b["ipos"]));
        assert!(
            (ours.com - ipos).length() <= 1e-12,
            "{name}: {} vs {ipos}",
            ours.com
        );
        let q = numbers(&b["iquat"]);
        let r = DMat3::from_quat(DQuat::from_xyzw(q[1], q[2], q[3], q[0]));
        let moments = DVec3::from_slice(&numbers(&b["inertia"]));
        let theirs = Symmetric3::from_diagonal(moments).rotate(&r);
        for (x, y) in ours.rotational.to_voigt().iter().zip(theirs.to_voigt()) {
            assert!(
                (x - y).abs() <= 1e-10 * moments.max_element(),
                "{name}: {:?} vs {theirs:?}",
                ours.rotational
            );
        }
    }
    // The legacy rule over-counts the L-shaped prism: the solid's exact mass would be 18 kg.
    assert!(link_mass(&model, "legacy") > 20.0);
}
