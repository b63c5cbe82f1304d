//! The fuzz targets as ordinary tests on stable: every committed seed (`fuzz/seeds/<target>/`,
//! plus the reference models and requests under `tests/data/reference/`) and a few thousand
//! generated inputs (proptest, fixed seed, so a run is reproducible) go through the same harness
//! as the libFuzzer targets (`fuzz/src/harness.rs`). The harness asserts that every outcome is
//! `Ok` with finite numbers or a typed error; a panic fails the test.
//!
//! Long campaigns: `cargo fuzz run <target>` (CONTRIBUTING.md, "Fuzzing").

#[allow(
    unreachable_pub,
    reason = "the harness is public in the fuzz crate, which shares this file"
)]
#[path = "../fuzz/src/harness.rs"]
mod harness;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The files of `dir` with extension `ext` (any extension when empty), sorted.
fn files(dir: &Path, ext: &str) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| ext.is_empty() || p.extension().is_some_and(|x| x == ext))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no seed in {}", dir.display());
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

fn seeds(target: &str) -> Vec<Vec<u8>> {
    files(&root().join("fuzz/seeds").join(target), "")
}

/// A runner with a fixed seed: the same inputs on every run.
fn runner(cases: u32) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    )
}

/// Mutations of the seeds: bytes replaced, inserted, removed or a span duplicated.
fn mutated(seeds: Vec<Vec<u8>>) -> impl Strategy<Value = Vec<u8>> {
    let n = seeds.len();
    (
        0..n,
        proptest::collection::vec((any::<u8>(), any::<u16>(), any::<u8>()), 1..6),
    )
        .prop_map(move |(k, edits)| {
            let mut s = seeds[k].clone();
            for (op, at, byte) in edits {
                let at = if s.is_empty() {
                    0
                } else {
                    at as usize % s.len()
                };
                match op % 4 {
                    0 if !s.is_empty() => s[at] = byte,
                    1 => s.insert(at, byte),
                    2 if !s.is_empty() => {
                        s.remove(at);
                    }
                    _ => {
                        let end = (at + byte as usize).min(s.len());
                        let span = s[at..end].to_vec();
                        s.splice(at..at, span);
                    }
                }
            }
            s
        })
}

#[test]
fn urdf_seeds_and_mutations() {
    let mut all = seeds("urdf");
    all.extend(files(&root().join("tests/data/reference/urdf"), "urdf"));
    for s in &all {
        harness::urdf(s);
    }
    runner(300)
        .run(&mutated(all), |s| {
            harness::urdf(&s);
            Ok(())
        })
        .unwrap();
}

#[test]
fn mjcf_seeds_and_mutations() {
    let mut all = seeds("mjcf");
    let models = root().join("tests/data/reference/mjcf/models");
    for model in [
        "gym_ant/ant.xml",
        "gym_hopper/hopper.xml",
        "dmc_ball_joints/model_with_ball_joints.xml",
        "dmc_testing_arm/arm.xml",
    ] {
        all.push(std::fs::read(models.join(model)).unwrap());
    }
    for s in &all {
        harness::mjcf(s);
    }
    runner(300)
        .run(&mutated(all), |s| {
            harness::mjcf(&s);
            Ok(())
        })
        .unwrap();
}

#[test]
fn json_seeds_and_mutations() {
    let all = seeds("json");
    for s in &all {
        harness::json(s);
    }
    runner(300)
        .run(&mutated(all), |s| {
            harness::json(&s);
            Ok(())
        })
        .unwrap();
}

#[test]
fn compute_seeds_and_generated_requests() {
    let mut all = seeds("compute");
    all.extend(
        files(&root().join("tests/data/reference"), "json")
            .into_iter()
            .filter(|f| f.len() < 200_000),
    );
    for s in &all {
        harness::compute(s);
    }
    // Requests with arbitrary joint names and values (NaN, inf and huge ones as JSON can carry
    // them: as numbers up to ±1.7e308 and as strings).
    let value = prop_oneof![
        any::<f64>().prop_filter("JSON numbers are finite", |x| x.is_finite()),
        Just(1e308),
        Just(-1e308),
        (-4.0f64..4.0),
    ];
    let joint = prop_oneof![
        (1..10u8).prop_map(|k| format!("panda_joint{k}")),
        Just("panda_finger_joint1".to_string()),
        "[a-z_]{0,12}",
    ];
    let map = proptest::collection::btree_map(joint, value, 0..10);
    let sample = (map.clone(), map.clone(), map.clone(), map);
    runner(400)
        .run(&proptest::collection::vec(sample, 0..3), |samples| {
            let samples: Vec<serde_json::Value> = samples
                .into_iter()
                .map(|(q, v, a, tau)| serde_json::json!({"q": q, "v": v, "a": a, "tau": tau}))
                .collect();
            let request = serde_json::json!({ "samples": samples });
            harness::compute(request.to_string().as_bytes());
            Ok(())
        })
        .unwrap();
}

#[test]
fn state_seeds_and_generated_bytes() {
    for s in seeds("state") {
        harness::state(&s);
    }
    runner(3000)
        .run(&proptest::collection::vec(any::<u8>(), 0..160), |s| {
            harness::state(&s);
            Ok(())
        })
        .unwrap();
}

#[test]
fn yapcad_seeds_mutations_and_generated_chains() {
    let all = seeds("yapcad");
    for s in &all {
        let _ = harness::yapcad(s);
        // The generic JSON loader recognises the shape and reads it the same way.
        harness::json(s);
    }
    runner(300)
        .run(&mutated(all), |s| {
            let _ = harness::yapcad(&s);
            Ok(())
        })
        .unwrap();
    // Generated chains: parts whose parents are earlier parts (or a datum, a later part, a
    // missing one), any joint type, and numbers at the edges of f64 in every field.
    let number = prop_oneof![
        4 => -200.0f64..200.0,
        1 => Just(0.0),
        1 => Just(1e308),
        1 => Just(-1e308),
        1 => Just(1e-310),
        1 => any::<f64>().prop_filter("JSON numbers are finite", |x| x.is_finite()),
    ];
    let triple = proptest::collection::vec(number.clone(), 3);
    let kind = prop_oneof![
        3 => Just("fixed"),
        3 => Just("revolute"),
        3 => Just("prismatic"),
        2 => Just("spherical"),
        1 => Just("bogus"),
    ];
    let part = (
        0..16usize,
        kind,
        number.clone(),
        triple.clone(),
        triple.clone(),
        triple.clone(),
        proptest::option::of(triple),
        proptest::option::of(number),
    );
    let loaded = std::cell::Cell::new(0);
    runner(1500)
        .run(&proptest::collection::vec(part, 1..7), |parts| {
            let mut doc = serde_json::Map::new();
            for (k, (parent, kind, value, axis, t, rot, world, tip)) in parts.iter().enumerate() {
                let parent = match *parent {
                    _ if k == 0 => "GLOBAL_DATUM".to_string(),
                    0 | 1 => "GLOBAL_DATUM".to_string(),
                    14 => format!("P{}", k + 1),
                    15 => "MISSING".to_string(),
                    p => format!("P{}", p % k),
                };
                let mut p = serde_json::json!({
                    "parent": parent,
                    "parent_frame": if tip.is_some() { "TIP" } else { "ORIGIN" },
                    "joint": {"name": format!("j{k}"), "type": kind, "axis": axis,
                              "value": value, "limits": [-180.0, 180.0],
                              "base_transform": {"translation": t, "rotation_xyz": rot}},
                });
                // Every part has a frame TIP (at a drawn height or 50 mm) for children to hang on.
                p["frames"] = serde_json::json!(
                    {"TIP": {"transform": {"translation": [0.0, 0.0, tip.unwrap_or(50.0)]}}});
                if let Some(w) = world {
                    p["world_transform"] = serde_json::json!({ "translation": w });
                }
                doc.insert(format!("P{k}"), p);
            }
            let text = serde_json::json!({"name": "generated", "parts": doc}).to_string();
            if harness::yapcad(text.as_bytes()) {
                loaded.set(loaded.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    // The refusals are not all there is: many generated chains load and run.
    assert!(loaded.get() > 100, "{} of 1500 loaded", loaded.get());
}
