//! End-to-end tests of `kinetree collide` and `kinetree ik`: hand-computed distances, the
//! bundled meshes, and IK answers that `compute` confirms.

mod common;

use common::*;

#[test]
fn collide_reports_hand_computed_distances() {
    // Two unit-radius balls, a on the base and b two joints out (adjacent links are never
    // candidates): centres 3 m apart at q = 0, so the signed distance is 1 m; at slide = -1.5
    // they overlap by 0.5 m. A 0.2 m ball obstacle at x = 5 is 0.8 m from b at q = 0.
    let dir = scratch("collide");
    let urdf = dir.join("balls.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="balls">
      <link name="a"><collision><geometry><sphere radius="1"/></geometry></collision></link>
      <link name="m"/>
      <link name="b"><collision><geometry><sphere radius="1"/></geometry></collision></link>
      <joint name="slide" type="prismatic"><parent link="a"/><child link="m"/><origin xyz="3 0 0"/>
        <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="turn" type="revolute"><parent link="m"/><child link="b"/>
        <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    </robot>"#,
    )
    .unwrap();
    let scene = dir.join("scene.json");
    std::fs::write(&scene, r#"{"obstacles": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.2}, "xyz": [5, 0, 0]}]}"#).unwrap();
    let o = kinetree(&[
        "collide",
        urdf.to_str().unwrap(),
        "--obstacles",
        scene.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = format!("\n{}", stdout(&o));
    assert!(text.contains("self-collisions: 0"), "{text}");
    let closest = section(&text, "closest self pairs");
    assert!(
        (row(closest, "a_0")[2].parse::<f64>().unwrap() - 1.0).abs() < 1e-9,
        "{text}"
    );
    let world = section(&text, "closest world pairs");
    assert!(
        (row(world, "b_0")[2].parse::<f64>().unwrap() - 0.8).abs() < 1e-9,
        "{text}"
    );
    let o = kinetree(&["collide", urdf.to_str().unwrap(), "--q", "slide=-1.5"]);
    let text = format!("\n{}", stdout(&o));
    assert!(text.contains("self-collisions: 1"), "{text}");
    assert!(
        (row(section(&text, "self-collisions"), "a_0")[3]
            .parse::<f64>()
            .unwrap()
            - 0.5)
            .abs()
            < 1e-9,
        "{text}"
    );
}

#[test]
fn collide_distance_tolerance_bounds_the_change() {
    // The closest pairs of panda_collision at the default 1e-8 and at 1e-3: each reported
    // distance is within tol · max(|d|, 1 mm) above the exact one, so the two lists differ by at
    // most 1e-3 · max(|d|, 1 mm) per pair (plus the printed rounding, 5e-7 m each), and the
    // pairs that GJK/EPA solve move visibly at 1e-3 (here an overlap of link 5 and the hand;
    // separated cylinders are solved on their features, mostly to round-off at any tolerance).
    let urdf = data("reference/urdf/panda_collision.urdf");
    let q = "panda_joint4=-0.3";
    let list = |extra: &[&str]| {
        let mut args = vec!["collide", urdf.as_str(), "--q", q, "--closest", "600"];
        args.extend_from_slice(extra);
        let o = kinetree(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = format!("\n{}", stdout(&o));
        section(&text, "closest self pairs")
            .lines()
            .skip(1)
            .map(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                (
                    (w[0].to_string(), w[1].to_string()),
                    w[2].parse::<f64>().unwrap(),
                )
            })
            .collect::<std::collections::BTreeMap<_, _>>()
    };
    let fine = list(&[]);
    let coarse = list(&["--distance-tolerance", "1e-3"]);
    assert_eq!(fine.len(), 513);
    assert_eq!(
        fine.keys().collect::<Vec<_>>(),
        coarse.keys().collect::<Vec<_>>()
    );
    let mut moved = 0;
    for (pair, f) in &fine {
        let change = coarse[pair] - f;
        let bound = 1e-3 * f.abs().max(1e-3);
        assert!(
            -1e-8 * f.abs().max(1e-3) - 1e-6 <= change && change <= bound + 1e-6,
            "{pair:?}: {f} -> {}",
            coarse[pair]
        );
        moved += usize::from(change != 0.0);
    }
    assert!(moved > 0);
    for bad in ["0", "1e-2", "nan"] {
        let o = kinetree(&["collide", urdf.as_str(), "--distance-tolerance", bad]);
        refused(&o, &["--distance-tolerance", "distance tolerance"]);
    }
}

#[test]
fn ik_solution_places_the_frame_where_compute_finds_it() {
    let o = kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "panda_hand_tcp",
        "--target",
        "0.4,0.2,0.5,3.14159,0,0",
        "--seed",
        "3",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(report["status"], "converged", "{report}");
    assert!(report["position_error"].as_f64().unwrap() < 1e-6);
    // Independent check: forward kinematics of the answer through `kinetree compute`.
    let dir = scratch("ik");
    let states = dir.join("states.json");
    std::fs::write(
        &states,
        serde_json::json!({"samples": [{"q": report["q"]}]}).to_string(),
    )
    .unwrap();
    let o = kinetree(&["compute", &panda(), "--states", states.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let result: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let pose = &result["samples"][0]["link_poses"]["panda_hand_tcp"];
    for (k, want) in [0.4, 0.2, 0.5].iter().enumerate() {
        assert!(
            (pose["translation"][k].as_f64().unwrap() - want).abs() < 1e-6,
            "{pose}"
        );
    }
    // roll = π about x: the tool's z axis points down.
    assert!(
        (pose["rotation"][2][2].as_f64().unwrap() + 1.0).abs() < 1e-5,
        "{pose}"
    );
    let o = kinetree(&[
        "ik",
        &panda(),
        "--frame",
        "no_such_frame",
        "--target",
        "0,0,0",
        "--position-only",
    ]);
    assert!(!o.status.success() && stderr(&o).contains("no_such_frame"));
}

#[test]
fn collide_finds_the_bundled_panda_meshes_with_no_flag() {
    let out = kinetree(&["collide", &panda()]);
    let text = stdout(&out);
    assert!(out.status.success(), "stderr: {}", stderr(&out));
    // 9 STL meshes and 8 finger boxes, none skipped.
    assert!(text.starts_with("panda: 17 shapes,"), "{text}");
    assert!(!stderr(&out).contains("skipped"), "{}", stderr(&out));
}
