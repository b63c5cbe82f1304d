//! One mesh lookup rule for every command: a relative mesh name is looked up next to the model
//! file first, then in the `--mesh-path` directories, whatever the working directory.
//! (`kinetree view` has the same test on its own state, in `cmd/view/tests.rs`.)

mod common;

use common::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A cube of side `side` centred at the origin, as OBJ.
fn cube(side: f64) -> String {
    let h = side / 2.0;
    let mut obj = String::new();
    for z in [-h, h] {
        for (x, y) in [(-h, -h), (h, -h), (h, h), (-h, h)] {
            obj.push_str(&format!("v {x} {y} {z}\n"));
        }
    }
    obj + "f 2 3 7 6\nf 1 5 8 4\nf 4 8 7 3\nf 1 2 6 5\nf 5 6 7 8\nf 1 4 3 2\n"
}

/// `root/model/robot.urdf`: links `a` and `b` each a `meshes/cube.obj` (a relative name), `b`
/// 3 m along x behind a massless middle link (so the pair is a candidate); `model/meshes` holds
/// a 1 m cube and `other/meshes` a 2 m cube, so the distance says which was found: 2 m for
/// the model's own, 1 m for the other.
fn robot(root: &Path) -> (PathBuf, PathBuf) {
    let model = root.join("model");
    let other = root.join("other");
    std::fs::create_dir_all(model.join("meshes")).unwrap();
    std::fs::create_dir_all(other.join("meshes")).unwrap();
    std::fs::write(model.join("meshes/cube.obj"), cube(1.0)).unwrap();
    std::fs::write(other.join("meshes/cube.obj"), cube(2.0)).unwrap();
    let mesh = r#"<collision><geometry><mesh filename="meshes/cube.obj"/></geometry></collision>
        <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>"#;
    let urdf = model.join("robot.urdf");
    std::fs::write(
        &urdf,
        format!(
            r#"<robot name="cubes">
      <link name="a">{mesh}</link>
      <link name="m"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="b">{mesh}</link>
      <joint name="slide" type="prismatic"><parent link="a"/><child link="m"/><origin xyz="3 0 0"/>
        <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="turn" type="revolute"><parent link="m"/><child link="b"/>
        <axis xyz="0 0 1"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
    </robot>"#
        ),
    )
    .unwrap();
    (urdf, other)
}

/// `kinetree args` run from `cwd`.
fn kinetree_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .current_dir(cwd)
        .args(args)
        .output()
        .expect("the kinetree binary runs")
}

#[test]
fn collide_finds_a_relative_mesh_next_to_the_model_before_the_mesh_paths() {
    let root = scratch("mesh-paths-collide");
    let (urdf, other) = robot(&root);
    // From another directory, with the model named relatively and absolutely.
    let elsewhere = root.join("other");
    for model in [urdf.to_str().unwrap(), "../model/robot.urdf"] {
        let o = kinetree_in(
            &elsewhere,
            &["collide", model, "--mesh-path", other.to_str().unwrap()],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let text = format!("\n{}", stdout(&o));
        let d: f64 = row(section(&text, "closest self pairs"), "a_0")[2]
            .parse()
            .unwrap();
        assert!((d - 2.0).abs() < 1e-9, "the model's own 1 m cubes: {text}");
    }
    // A mesh missing next to the model is found in a --mesh-path directory.
    std::fs::remove_file(urdf.with_file_name("meshes/cube.obj")).unwrap();
    let o = kinetree_in(
        &root,
        &[
            "collide",
            urdf.to_str().unwrap(),
            "--mesh-path",
            other.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = format!("\n{}", stdout(&o));
    let d: f64 = row(section(&text, "closest self pairs"), "a_0")[2]
        .parse()
        .unwrap();
    assert!(
        (d - 1.0).abs() < 1e-9,
        "the 2 m cubes of --mesh-path: {text}"
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn bench_finds_relative_meshes_by_the_same_rule() {
    let root = scratch("mesh-paths-bench");
    let (urdf, other) = robot(&root);
    let bench = |cwd: &Path, extra: &[&str]| {
        let mut args = vec![
            "bench",
            urdf.to_str().unwrap(),
            "--calls",
            "10",
            "--repetitions",
            "1",
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = kinetree_in(cwd, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        let doc: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
        let times = doc["ns_per_call"].as_object().unwrap();
        // The row at coal's distance tolerance comes with the default one.
        assert_eq!(
            times.contains_key("collision_distances"),
            times.contains_key("collision_distances_tol1e-6")
        );
        times.contains_key("collision_distances")
    };
    // Next to the model, from another working directory: the collision timings are there.
    assert!(bench(&other, &[]));
    // Missing next to the model: found through --mesh-path, skipped without it.
    std::fs::remove_file(urdf.with_file_name("meshes/cube.obj")).unwrap();
    assert!(!bench(&root, &[]));
    assert!(bench(&root, &["--mesh-path", other.to_str().unwrap()]));
    std::fs::remove_dir_all(&root).unwrap();
}
