//! Hostile input through the binary: every command on degenerate models, closed pipes, absurd
//! work and overflowing states ends with a result or a clean refusal (exit code 1 and a message
//! naming the problem), never a panic, a hang or a NaN printed as an answer.

mod common;

use common::*;
use std::io::Write;
use std::process::{Command, Output, Stdio};

#[test]
fn a_non_unit_floating_quaternion_is_refused_naming_the_joint_and_norm() {
    // (x, y, z, w) = (1, 0, 0, 1): norm √2, which used to double the torques.
    let o = kinetree(&[
        "dynamics",
        &panda(),
        "--floating",
        "--q",
        "root_joint=0:0:0:1:0:0:1",
        "--a",
        "panda_joint1=0",
    ]);
    refused(&o, &["root_joint", "1.414213562"]);
    // The zero quaternion is not the identity.
    let o = kinetree(&[
        "dynamics",
        &panda(),
        "--floating",
        "--q",
        "root_joint=0:0:0:0:0:0:0",
        "--a",
        "panda_joint1=0",
    ]);
    refused(&o, &["root_joint", "norm 0"]);
}

#[test]
fn an_overflowing_state_is_an_error_not_nan() {
    let o = kinetree(&[
        "dynamics",
        &panda(),
        "--v",
        "panda_joint1=1e308",
        "--a",
        "panda_joint1=0",
    ]);
    refused(&o, &["overflowed", "panda_joint"]);
    assert!(!stdout(&o).contains("NaN") && !stdout(&o).contains("inf"));
    // A runaway simulation says it diverged instead of blaming massless links.
    let o = kinetree(&["simulate", &panda(), "--v", "panda_joint1=1e6"]);
    refused(&o, &["diverged"]);
}

#[test]
fn bench_refuses_counts_that_time_nothing_or_never_finish() {
    let o = kinetree(&["bench", &panda(), "--calls", "0", "--repetitions", "0"]);
    refused(&o, &["--calls", "at least 1"]);
    let o = kinetree(&["bench", &panda(), "--calls", "18446744073709551615"]);
    refused(&o, &["limit", "--no-limit"]);
}

#[test]
fn absurd_work_is_refused_with_the_limit_and_how_to_lift_it() {
    let o = kinetree(&["simulate", &panda(), "--duration", "1e300"]);
    refused(&o, &["limit", "--no-limit"]);
    let o = kinetree(&["simulate", &panda(), "--dt", "1e-300"]);
    refused(&o, &["limit", "--no-limit"]);
    let o = kinetree(&[
        "workspace",
        &panda(),
        "--frame",
        "panda_link8",
        "--threads",
        "100000",
    ]);
    refused(&o, &["--threads 100000", "limit", "--no-limit"]);
    #[cfg(unix)]
    {
        let o = kinetree(&["inspect", "/dev/zero"]);
        refused(&o, &["/dev/zero", "not a regular file"]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(["inspect", &panda()])
        .env("KINETREE_MAX_MODEL_BYTES", "1000")
        .output()
        .unwrap();
    refused(&o, &["limit of 1000", "KINETREE_MAX_MODEL_BYTES"]);
}

/// `kinetree … | head -c 0`: the reader is gone before the command writes.
fn with_closed_stdout(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    child.wait_with_output().unwrap()
}

#[test]
fn a_closed_stdout_is_a_normal_end() {
    let reference = data("reference/panda.json");
    let urdf = data("reference/urdf/panda.urdf");
    for args in [
        vec!["inspect", &panda()],
        vec!["compute", &urdf, "--states", &reference],
        vec!["simulate", &panda(), "--duration", "0.01"],
        vec!["dynamics", &panda(), "--a", "panda_joint1=1"],
    ] {
        let o = with_closed_stdout(&args);
        let err = stderr(&o);
        assert!(o.status.success(), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn every_command_works_or_refuses_cleanly_on_degenerate_models() {
    let dir = scratch("degenerate");
    let one = dir.join("one.urdf");
    std::fs::write(&one, r#"<robot name="one"><link name="a"/></robot>"#).unwrap();
    let empty = dir.join("empty.urdf");
    std::fs::write(&empty, r#"<robot name="e"/>"#).unwrap();
    let states = dir.join("states.json");
    std::fs::write(&states, r#"{"samples": [{"q": {}}]}"#).unwrap();
    let json = dir.join("out.json");
    for model in [&one, &empty] {
        let m = model.to_str().unwrap();
        for args in [
            vec!["inspect", m],
            vec!["convert", m, json.to_str().unwrap()],
            vec!["compute", m, "--states", states.to_str().unwrap()],
            vec!["bench", m, "--calls", "10", "--repetitions", "1"],
            vec!["ik", m, "--frame", "a", "--position", "0,0,0"],
            vec!["collide", m],
            vec!["dynamics", m],
            vec!["simulate", m, "--duration", "0.01"],
            vec!["workspace", m, "--frame", "a", "--samples", "10"],
        ] {
            let o = kinetree(&args);
            let err = stderr(&o);
            assert!(
                matches!(o.status.code(), Some(0..=2)),
                "{args:?}: {:?} {err}",
                o.status
            );
            assert!(!err.contains("panicked"), "{args:?}: {err}");
            if !o.status.success() {
                assert!(err.starts_with("error"), "{args:?}: {err}");
            }
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn inspect_output_grows_linearly_with_depth() {
    // A 3000-link chain: indenting one level per depth printed 9 MB of spaces.
    let n = 3000;
    let mut urdf = String::from(r#"<robot name="chain"><link name="l0"/>"#);
    for i in 1..n {
        urdf.push_str(&format!(
            r#"<link name="l{i}"/><joint name="j{i}" type="fixed"><parent link="l{}"/><child link="l{i}"/></joint>"#,
            i - 1
        ));
    }
    urdf.push_str("</robot>");
    let dir = scratch("chain");
    let path = dir.join("chain.urdf");
    std::fs::File::create(&path)
        .unwrap()
        .write_all(urdf.as_bytes())
        .unwrap();
    let o = kinetree(&["inspect", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.len() < 1_000_000, "{} bytes", text.len());
    assert!(text.contains("[depth 2999] l2999"), "{}", &text[..2000]);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_non_finite_joint_value_is_named_not_indexed() {
    // `=NaN` used to say "value 0 is not finite": 0 was an index, not the value.
    let o = kinetree(&["dynamics", &panda(), "--q", "panda_joint1=NaN", "--a", "0"]);
    refused(
        &o,
        &[
            "joint 'panda_joint1'",
            "position NaN is not a finite number",
        ],
    );
    assert!(!stderr(&o).contains("value 0"), "{}", stderr(&o));
    let o = kinetree(&["dynamics", &panda(), "--v", "panda_joint2=-inf", "--a", "0"]);
    refused(
        &o,
        &[
            "joint 'panda_joint2'",
            "velocity -inf is not a finite number",
        ],
    );
    // In a multi-value joint the position is an ordinal of the joint's own values.
    let o = kinetree(&[
        "dynamics",
        &panda(),
        "--floating",
        "--q",
        "root_joint=0:0:0:0:0:inf:1",
        "--a",
        "0",
    ]);
    refused(&o, &["joint 'root_joint'", "inf", "value 6 of 7"]);
}

#[test]
fn a_model_file_in_the_wrong_encoding_says_so() {
    let dir = scratch("encoding");
    let text = std::fs::read_to_string(panda()).unwrap();
    // UTF-16 little-endian with a byte-order mark, as some Windows editors save.
    let mut utf16 = vec![0xFF, 0xFE];
    utf16.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
    let path = dir.join("utf16.urdf");
    std::fs::write(&path, utf16).unwrap();
    let o = kinetree(&["inspect", path.to_str().unwrap()]);
    refused(&o, &["UTF-16", "must be UTF-8", "iconv"]);
    assert!(!stderr(&o).contains("cannot access"), "{}", stderr(&o));
    let path = dir.join("binary.json");
    std::fs::write(&path, [b'{', 0xC3, 0x28, 0xFF, b'}']).unwrap();
    let o = kinetree(&["inspect", path.to_str().unwrap()]);
    refused(&o, &["not UTF-8 text", "offset 1"]);
    assert!(!stderr(&o).contains("cannot access"), "{}", stderr(&o));
}

#[test]
fn a_xacro_file_is_recognised_and_the_expansion_suggested() {
    let dir = scratch("xacro");
    let with_property = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="l" value="0.5"/>
  <link name="base"><visual><geometry><box size="${l} 1 1"/></geometry></visual></link>
</robot>"#;
    let path = dir.join("arm.urdf.xacro");
    std::fs::write(&path, with_property).unwrap();
    let o = kinetree(&["inspect", path.to_str().unwrap()]);
    let expand = format!(
        "`xacro {} > {}`",
        path.display(),
        dir.join("arm.urdf").display()
    );
    refused(
        &o,
        &["looks like a xacro file", "<xacro:property>", &expand],
    );
    // Only an unexpanded expression left, no xacro element.
    let path = dir.join("leftover.urdf");
    std::fs::write(
        &path,
        with_property.replace("<xacro:property name=\"l\" value=\"0.5\"/>", ""),
    )
    .unwrap();
    let o = kinetree(&["inspect", path.to_str().unwrap()]);
    refused(&o, &["looks like a xacro file", "${l}", "expand it first"]);
}

#[test]
fn sampling_a_workspace_with_huge_limits_never_blames_a_q_the_user_did_not_give() {
    let dir = scratch("huge-limits");
    let path = dir.join("rail.urdf");
    std::fs::write(
        &path,
        r#"<robot name="rail"><link name="base"/>
<link name="cart"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="slide" type="prismatic"><parent link="base"/><child link="cart"/><axis xyz="1 0 0"/>
<limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint></robot>"#,
    )
    .unwrap();
    let p = path.to_str().unwrap();
    // The samples are finite (the limit width 2e308 overflows, the limits do not); what cannot be
    // done is binning points that far out into 2 cm voxels, and that is what is said.
    let o = kinetree(&["workspace", p, "--frame", "cart", "--samples", "100"]);
    refused(&o, &["voxel size 0.02 m is too small"]);
    assert!(!stderr(&o).contains("q[0]"), "{}", stderr(&o));
    let o = kinetree(&["workspace", p, "--frame", "cart", "--grid", "3"]);
    refused(&o, &["voxel size 0.02 m is too small"]);
}

#[test]
fn skipped_meshes_are_listed_one_readable_line_each() {
    let dir = scratch("skipped-meshes");
    let path = dir.join("m.urdf");
    std::fs::write(
        &path,
        r#"<robot name="m"><link name="base"><collision><geometry><mesh filename="nowhere/gone.stl"/></geometry></collision></link>
<link name="arm"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#,
    )
    .unwrap();
    let states = dir.join("states.json");
    std::fs::write(&states, r#"{"samples":[{}]}"#).unwrap();
    let p = path.to_str().unwrap();
    for o in [
        kinetree(&["collide", p, "--skip-missing-meshes"]),
        kinetree(&[
            "compute",
            p,
            "--states",
            states.to_str().unwrap(),
            "--collision",
            "--skip-missing-meshes",
        ]),
    ] {
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(0), "{err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.contains("gone.stl")).collect();
        assert_eq!(lines.len(), 1, "{err}");
        assert!(
            lines[0].starts_with(
                "skipped mesh: mesh 'nowhere/gone.stl' (link 'base', collision 0) left out: "
            ),
            "{err}"
        );
        assert!(!err.contains("SkippedMesh"), "{err}");
    }
}

#[test]
fn an_invalid_obstacle_is_called_an_obstacle_not_a_link() {
    let dir = scratch("obstacle");
    let scene = dir.join("scene.json");
    std::fs::write(
        &scene,
        r#"{"obstacles":[{"name":"t","geometry":{"type":"sphere","radius":-1}}]}"#,
    )
    .unwrap();
    let o = kinetree(&["collide", &panda(), "--obstacles", scene.to_str().unwrap()]);
    refused(&o, &["obstacle 't'", "radius = -1"]);
    assert!(!stderr(&o).contains("link 't'"), "{}", stderr(&o));
    assert_eq!(stderr(&o).matches("'t'").count(), 1, "{}", stderr(&o));
}

#[test]
fn an_unknown_field_in_a_compute_states_file_is_refused() {
    let dir = scratch("compute-fields");
    let states = dir.join("states.json");
    for (text, field) in [
        (
            r#"{"samples":[{"q":{"panda_joint1":0.1},"tua":{"panda_joint1":1}}]}"#,
            "'tua'",
        ),
        (
            r#"{"samples":[{"name":"s","state":{"q":{"panda_joint1":0.1},"vv":{}}}]}"#,
            "'vv'",
        ),
    ] {
        std::fs::write(&states, text).unwrap();
        let o = kinetree(&["compute", &panda(), "--states", states.to_str().unwrap()]);
        refused(&o, &["sample 0", "unknown field", field]);
    }
    // A reference sample keeps its results beside `state`: those are not the state.
    std::fs::write(
        &states,
        r#"{"samples":[{"name":"s","state":{"q":{"panda_joint1":0.1}},"rnea":[1,2]}]}"#,
    )
    .unwrap();
    let o = kinetree(&["compute", &panda(), "--states", states.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn a_neutral_start_outside_the_limits_is_said_and_clamped() {
    // The Panda's joint 4 has limits [-3.0718, -0.0698]: its neutral value 0 is outside.
    let o = kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "panda_hand",
        "--target",
        "0.4,0.1,0.5",
        "--position-only",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("neutral configuration is outside the joint limits"),
        "{}",
        stderr(&o)
    );
    let text = stdout(&o);
    assert!(text.starts_with("status: converged"), "{text}");
    // The count of restarts agrees with its noun.
    assert!(
        text.contains(" 1 restart,") || text.contains(" 0 restarts,"),
        "{text}"
    );
    // collide computes at the state it is given, and says when it is outside the limits.
    let o = kinetree(&["collide", &panda()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "the neutral configuration puts joint 'panda_joint4' at 0, outside its limits"
        ),
        "{}",
        stderr(&o)
    );
    let o = kinetree(&["collide", &panda(), "--q", "panda_joint4=-1.5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("outside its limits"), "{}", stderr(&o));
}

#[test]
fn floating_says_when_it_has_no_effect() {
    // A yapCAD assembly attaches its root part to the world by its own joint.
    let yap = data("yapcad/yap_arm.yapcad.json");
    let o = kinetree(&["inspect", &yap, "--floating"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--floating has no effect on") && stderr(&o).contains("yap_arm"),
        "{}",
        stderr(&o)
    );
    // A URDF gets its floating root joint, and no note.
    let o = kinetree(&["inspect", &panda(), "--floating"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("root_joint"), "{}", stdout(&o));
    assert!(!stderr(&o).contains("no effect"), "{}", stderr(&o));
}
