//! Tests of the viewer's server on an ephemeral port, through a raw HTTP/1.1 client.

use super::api::pose;
use super::{Args, State, server};
use kinetree::kinematics::configuration::random_configuration;
use kinetree::kinematics::{KinematicsData, forward_kinematics};
use kinetree::model::Model;
use rand::SeedableRng;
use serde_json::{Value, json};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

mod attacks;

fn panda_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/robots/panda.urdf")
}

fn serve(args: &Args) -> (server::Running, Arc<State>) {
    let state = Arc::new(State::new(args).unwrap());
    (
        server::start(Arc::clone(&state), "127.0.0.1", 0, 4).unwrap(),
        state,
    )
}

fn panda_args() -> Args {
    Args {
        model: panda_path(),
        no_open: true,
        ..Args::default()
    }
}

/// A raw connection to the server on loopback that gives up reading or writing after 30 s.
fn raw_client(port: u16) -> TcpStream {
    let s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    s.set_write_timeout(Some(Duration::from_secs(30))).unwrap();
    s
}

/// One request on a fresh connection: (status, body).
fn http(port: u16, method: &str, path: &str, body: &[u8]) -> (u16, Vec<u8>) {
    let mut s = raw_client(port);
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    s.write_all(head.as_bytes()).unwrap();
    // The server may answer (413) before reading a large body and close: ignore write errors.
    let _ = s.write_all(body);
    let mut out = Vec::new();
    let _ = s.read_to_end(&mut out);
    let end = out
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .unwrap_or_else(|| panic!("no header end in {:?}", String::from_utf8_lossy(&out)));
    let head = String::from_utf8_lossy(&out[..end]).into_owned();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, out[end + 4..].to_vec())
}

fn post_json(port: u16, path: &str, body: &Value) -> (u16, Value) {
    let (status, bytes) = http(port, "POST", path, body.to_string().as_bytes());
    (status, serde_json::from_slice(&bytes).unwrap())
}

/// The library's link poses at `q`.
fn library_links(model: &Model, q: &[f64]) -> Vec<[f64; 7]> {
    let mut data = KinematicsData::new(model);
    forward_kinematics(model, &mut data, q).unwrap();
    data.world_from_link().iter().map(pose).collect()
}

fn assert_links_equal(answer: &Value, expected: &[[f64; 7]]) {
    let links = answer["links"].as_array().unwrap();
    assert_eq!(links.len(), expected.len());
    for (a, e) in links.iter().zip(expected) {
        for (x, y) in a.as_array().unwrap().iter().zip(e) {
            assert!((x.as_f64().unwrap() - y).abs() <= 1e-12, "{a} vs {e:?}");
        }
    }
}

#[test]
fn fk_answers_equal_the_library() {
    let (running, state) = serve(&panda_args());
    let model = &state.model;
    let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
    for _ in 0..5 {
        let mut q = vec![0.0; model.nq()];
        random_configuration(model, &mut rng, &mut q).unwrap();
        let expected = library_links(model, &q);
        let (status, answer) = post_json(running.port, "/api/fk", &json!({ "q": q }));
        assert_eq!(status, 200, "{answer}");
        assert_links_equal(&answer, &expected);
        // The same configuration by joint name.
        let by_name: serde_json::Map<String, Value> = model
            .moving_joints()
            .map(|j| {
                let name = model.joint(j).name.clone();
                (name, json!(q[model.joint_q_range(j).start]))
            })
            .collect();
        let (status, answer) = post_json(running.port, "/api/fk", &json!({ "q": by_name }));
        assert_eq!(status, 200, "{answer}");
        assert_links_equal(&answer, &expected);
    }
    // The model description: 13 links, 9 moving joints, mesh URLs that serve the files.
    let (status, bytes) = http(running.port, "GET", "/api/model", b"");
    assert_eq!(status, 200);
    let m: Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(m["links"].as_array().unwrap().len(), 13);
    assert_eq!(m["joints"].as_array().unwrap().len(), 9);
    let url = m["links"][0]["collisions"][0]["geometry"]["url"]
        .as_str()
        .unwrap()
        .to_string();
    let (status, bytes) = http(running.port, "GET", &url, b"");
    assert_eq!(status, 200, "{url}");
    let file = panda_path()
        .parent()
        .unwrap()
        .join("panda_description/meshes/collision/link0.stl");
    assert_eq!(bytes, std::fs::read(file).unwrap());
    running.stop();
}

#[test]
fn ik_answers_reach_the_target() {
    let (running, state) = serve(&panda_args());
    let model = &state.model;
    let hand = model.link_index("panda_hand").unwrap();
    let mut rng = rand::rngs::SmallRng::seed_from_u64(11);
    for _ in 0..3 {
        let mut q_goal = vec![0.0; model.nq()];
        random_configuration(model, &mut rng, &mut q_goal).unwrap();
        let target = library_links(model, &q_goal)[hand];
        let body = json!({
            "frame": "panda_hand",
            "target": {"xyz": &target[..3], "quat": &target[3..]},
        });
        let (status, answer) = post_json(running.port, "/api/ik", &body);
        assert_eq!(status, 200, "{answer}");
        assert_eq!(answer["status"], "converged", "{answer}");
        // Check the answer with the library's FK, not the server's.
        let q: Vec<f64> = answer["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let reached = library_links(model, &q)[hand];
        for k in 0..3 {
            assert!(
                (reached[k] - target[k]).abs() < 1e-5,
                "{reached:?} vs {target:?}"
            );
        }
        let dot: f64 = (3..7).map(|k| reached[k] * target[k]).sum();
        assert!(
            dot.abs() > 1.0 - 1e-8,
            "orientation {reached:?} vs {target:?}"
        );
        assert_links_equal(&answer, &library_links(model, &q));
    }
    running.stop();
}

#[test]
fn bad_requests_get_their_status_and_the_server_keeps_serving() {
    // A mesh directory with a symlink that leads out of it.
    let dir = std::env::temp_dir().join(format!("kinetree-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let outside = dir.with_extension("secret");
    std::fs::write(&outside, "secret").unwrap();
    let link = dir.join("escape.stl");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&outside, &link).unwrap();
    let args = Args {
        mesh_paths: vec![dir.clone()],
        ..panda_args()
    };
    let (running, _) = serve(&args);
    let port = running.port;
    let big = vec![b' '; (1 << 20) + 1];
    let cases: Vec<(&str, &str, Vec<u8>, u16, &str)> = vec![
        ("POST", "/api/fk", b"{".to_vec(), 400, "not valid JSON"),
        ("POST", "/api/fk", b"[1, 2]".to_vec(), 400, "JSON object"),
        (
            "POST",
            "/api/fk",
            br#"{"q": {"nope": 1}}"#.to_vec(),
            400,
            "unknown joint 'nope'",
        ),
        (
            "POST",
            "/api/fk",
            br#"{"q": [1, 2]}"#.to_vec(),
            400,
            "must have 9 numbers, got 2",
        ),
        (
            "POST",
            "/api/fk",
            br#"{"q": {"panda_joint1": "NaN"}}"#.to_vec(),
            400,
            "finite number",
        ),
        (
            "POST",
            "/api/fk",
            br#"{"q": {"panda_joint1": NaN}}"#.to_vec(),
            400,
            "not valid JSON",
        ),
        (
            "POST",
            "/api/fk",
            br#"{"q": {"panda_joint1": 1e999}}"#.to_vec(),
            400,
            "not valid JSON",
        ),
        (
            "POST",
            "/api/fk",
            br#"{"q": {"panda_joint1": [1, 2]}}"#.to_vec(),
            400,
            "panda_joint1",
        ),
        ("POST", "/api/fk", br#"{"q": 3}"#.to_vec(), 400, "q must be"),
        (
            "POST",
            "/api/ik",
            br#"{"target": {"xyz": [0, 0, 1]}}"#.to_vec(),
            400,
            "ik needs",
        ),
        (
            "POST",
            "/api/ik",
            br#"{"frame": "nope", "target": {"xyz": [0, 0, 1]}}"#.to_vec(),
            400,
            "nope",
        ),
        (
            "POST",
            "/api/ik",
            br#"{"frame": "panda_hand", "target": {"xyz": [0, 0]}}"#.to_vec(),
            400,
            "target.xyz",
        ),
        (
            "POST",
            "/api/ik",
            br#"{"frame": "panda_hand", "target": {"xyz": [0, 0, 1], "quat": [0, 0, 0, 0]}}"#
                .to_vec(),
            400,
            "zero",
        ),
        (
            "POST",
            "/api/collide",
            br#"{"q": {"panda_joint9": 0}}"#.to_vec(),
            400,
            "panda_joint9",
        ),
        ("POST", "/api/fk", big.clone(), 413, "larger than"),
        ("POST", "/api/ik", big, 413, "larger than"),
        ("GET", "/api/fk", Vec::new(), 405, "POST"),
        ("GET", "/nowhere", Vec::new(), 404, "no such page"),
        (
            "GET",
            "/meshes/0/../panda.urdf",
            Vec::new(),
            404,
            "no such mesh",
        ),
        (
            "GET",
            "/meshes/0/%2E%2E/panda.urdf",
            Vec::new(),
            404,
            "no such mesh",
        ),
        (
            "GET",
            "/meshes/0//etc/passwd",
            Vec::new(),
            404,
            "no such mesh",
        ),
        (
            "GET",
            "/meshes/0/%2Fetc%2Fpasswd",
            Vec::new(),
            404,
            "no such mesh",
        ),
        (
            "GET",
            "/meshes/1/escape.stl",
            Vec::new(),
            404,
            "no such mesh",
        ),
        (
            "GET",
            "/meshes/7/panda.urdf",
            Vec::new(),
            404,
            "no such mesh",
        ),
        ("GET", "/meshes/x", Vec::new(), 404, "no such mesh"),
    ];
    for (method, path, body, status, message) in cases {
        let (got, answer) = http(port, method, path, &body);
        let text = String::from_utf8_lossy(&answer);
        assert_eq!(got, status, "{method} {path}: {text}");
        assert!(text.contains(message), "{method} {path}: {text}");
        // Still serving, and still right.
        let (ok, _) = http(port, "GET", "/api/model", b"");
        assert_eq!(ok, 200, "after {method} {path}");
    }
    // The model file itself is not a mesh: the model's directory is not served.
    let (status, _) = http(port, "GET", "/meshes/0/panda.urdf", b"");
    assert_eq!(status, 404);
    running.stop();
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_file(&outside).unwrap();
}

#[test]
fn a_thousand_concurrent_fk_requests_from_eight_threads_all_answer_right() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    let threads: Vec<_> = (0..8u64)
        .map(|t| {
            let state = Arc::clone(&state);
            std::thread::spawn(move || {
                let model = &state.model;
                let mut rng = rand::rngs::SmallRng::seed_from_u64(100 + t);
                let mut q = vec![0.0; model.nq()];
                for _ in 0..125 {
                    random_configuration(model, &mut rng, &mut q).unwrap();
                    let (status, answer) = post_json(port, "/api/fk", &json!({ "q": q }));
                    assert_eq!(status, 200, "{answer}");
                    assert_links_equal(&answer, &library_links(model, &q));
                }
                125
            })
        })
        .collect();
    let answered: usize = threads.into_iter().map(|t| t.join().unwrap()).sum();
    assert_eq!(answered, 1000);
    running.stop();
}

#[test]
fn collide_names_the_pairs_and_their_distances() {
    let (running, _) = serve(&panda_args());
    let (status, answer) = post_json(running.port, "/api/collide", &json!({}));
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["available"], true);
    let pairs = answer["pairs"].as_array().unwrap();
    // 17 shapes, adjacent links filtered: the same candidate pairs as `kinetree collide`.
    assert_eq!(pairs.len(), 99);
    for p in pairs {
        let d = p["distance"].as_f64().unwrap();
        assert_eq!(p["colliding"].as_bool().unwrap(), d < 0.0, "{p}");
    }
    running.stop();
}

#[test]
fn distance_tolerance_flag_sets_the_collision_model_and_refuses_bad_values() {
    let state = State::new(&Args {
        distance_tolerance: Some(1e-6),
        ..panda_args()
    })
    .unwrap();
    let cmodel = state.collision.as_ref().unwrap();
    assert_eq!(cmodel.distance_tolerance(), 1e-6);
    let default = State::new(&panda_args()).unwrap();
    assert_eq!(
        default.collision.as_ref().unwrap().distance_tolerance(),
        1e-8
    );
    for bad in [1.0, 0.0, -1e-6, f64::NAN, 1e-13] {
        let e = State::new(&Args {
            distance_tolerance: Some(bad),
            ..panda_args()
        })
        .unwrap_err();
        assert!(
            format!("{e:#}").contains("--distance-tolerance"),
            "{bad}: {e:#}"
        );
    }
}

#[test]
fn base64_matches_the_rfc_examples() {
    use super::page::base64;
    for (plain, encoded) in [
        ("", ""),
        ("f", "Zg=="),
        ("fo", "Zm8="),
        ("foo", "Zm9v"),
        ("foob", "Zm9vYg=="),
        ("fooba", "Zm9vYmE="),
        ("foobar", "Zm9vYmFy"),
    ] {
        assert_eq!(base64(plain.as_bytes()), encoded);
    }
}

#[test]
fn trajectory_files_are_checked_and_posed() {
    let dir = std::env::temp_dir().join(format!("kinetree-view-traj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("good.json");
    std::fs::write(
        &good,
        r#"{"trajectory": [{"t": 0, "q": {"panda_joint1": 0}}, {"t": 0.5, "q": {"panda_joint1": 1.0}}]}"#,
    )
    .unwrap();
    let state = State::new(&Args {
        trajectory: Some(good),
        ..panda_args()
    })
    .unwrap();
    let tr = &state.trajectory;
    assert_eq!(tr["t"], json!([0.0, 0.5]));
    let mut q = kinetree::kinematics::configuration::neutral_configuration(&state.model);
    q[0] = 1.0;
    assert_links_equal(
        &json!({"links": tr["links"][1]}),
        &library_links(&state.model, &q),
    );
    for (text, message) in [
        (r#"{"trajectory": []}"#, "empty"),
        (r#"{"trajectory": [{"q": {}}]}"#, "\"t\""),
        (
            r#"{"trajectory": [{"t": 1, "q": {}}, {"t": 0, "q": {}}]}"#,
            "decrease",
        ),
        (
            r#"{"trajectory": [{"t": 0, "q": {"nope": 1}}]}"#,
            "unknown joint 'nope'",
        ),
    ] {
        let bad = dir.join("bad.json");
        std::fs::write(&bad, text).unwrap();
        let e = State::new(&Args {
            trajectory: Some(bad),
            ..panda_args()
        })
        .unwrap_err();
        assert!(format!("{e:#}").contains(message), "{text}: {e:#}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every number in an answer is finite (serde_json writes NaN and inf as `null`, so a `null`
/// where a number belongs is a NaN that escaped).
fn assert_no_null_numbers(v: &Value, endpoint: &str, body: &[u8]) {
    match v {
        Value::Null => panic!(
            "null (a NaN or inf) in the {endpoint} answer to {}",
            String::from_utf8_lossy(body)
        ),
        Value::Number(n) => assert!(n.as_f64().is_some_and(f64::is_finite)),
        Value::Array(a) => a
            .iter()
            .for_each(|x| assert_no_null_numbers(x, endpoint, body)),
        Value::Object(o) => o
            .values()
            .for_each(|x| assert_no_null_numbers(x, endpoint, body)),
        Value::Bool(_) | Value::String(_) => {}
    }
}

/// The stable fuzz harness of the viewer's HTTP bodies (issue #11): the committed seeds in
/// `fuzz/seeds/view` and a few thousand bodies built from hostile pieces and byte mutations go
/// through `/api/fk`, `/api/ik` and `/api/collide` directly. Each answer is a 400 with a message
/// or a 200 without NaN; a panic fails the test.
#[test]
fn fuzzed_api_bodies_get_an_answer_or_a_bad_request() {
    use super::api;
    use rand::Rng;
    // The model and collision model exactly as `kinetree view` builds them (meshes found).
    let state = State::new(&panda_args()).unwrap();
    let (model, cmodel) = (&state.model, state.collision.as_ref().unwrap());
    let seeds_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/view");
    let mut seeds: Vec<Vec<u8>> = std::fs::read_dir(&seeds_dir)
        .unwrap()
        .map(|e| std::fs::read(e.unwrap().path()).unwrap())
        .collect();
    assert!(
        seeds.len() >= 7,
        "the seed corpus is in {}",
        seeds_dir.display()
    );
    // Hostile pieces: numbers at the edges of f64, wrong types, wrong lengths, unknown names;
    // ordinary values are listed several times so that many bodies are valid.
    let numbers = [
        "0", "0.5", "-0.3", "1", "0.02", "0", "0.5", "-0.3", "1", "0.02", "-0", "1e308", "-1e308",
        "5e-324", "1e-310", "3.14159", "1e999", "-1e999", "\"1\"", "null", "true", "[]", "{}",
    ];
    let names = [
        "panda_joint1",
        "panda_joint7",
        "panda_finger_joint2",
        "nope",
        "",
    ];
    let frames = ["panda_hand", "panda_link0", "panda_leftfinger", "nope", ""];
    let mut rng = rand::rngs::SmallRng::seed_from_u64(11);
    fn pick<'a>(rng: &mut rand::rngs::SmallRng, xs: &[&'a str]) -> &'a str {
        xs[rng.random_range(0..xs.len())]
    }
    for _ in 0..1500 {
        let r = &mut rng;
        let q = match r.random_range(0..3) {
            0 => format!(
                "{{\"{}\": {}, \"{}\": {}}}",
                pick(r, &names),
                pick(r, &numbers),
                pick(r, &names),
                pick(r, &numbers)
            ),
            1 => {
                let n = r.random_range(0..11);
                let values: Vec<&str> = (0..n).map(|_| pick(r, &numbers)).collect();
                format!("[{}]", values.join(","))
            }
            _ => pick(r, &numbers).to_string(),
        };
        let v: Vec<&str> = (0..7).map(|_| pick(r, &numbers)).collect();
        let frame = pick(r, &frames);
        seeds.push(
            format!(
                "{{\"q\": {q}, \"frame\": \"{frame}\", \"target\": {{\"xyz\": [{}, {}, {}], \"quat\": [{}, {}, {}, {}]}}}}",
                v[0], v[1], v[2], v[3], v[4], v[5], v[6]
            )
            .into_bytes(),
        );
    }
    // Byte mutations of everything so far: flips, cuts and insertions.
    let count = seeds.len();
    for k in 0..1500 {
        let mut body = seeds[k % count].clone();
        for _ in 0..rng.random_range(1..4) {
            let at = rng.random_range(0..=body.len());
            match rng.random_range(0..3) {
                0 if at < body.len() => body[at] ^= 1 << rng.random_range(0..8),
                1 => body.truncate(at),
                _ => body.insert(at, rng.random()),
            }
        }
        seeds.push(body);
    }
    let (mut ok, mut bad) = (0, 0);
    for body in &seeds {
        for (endpoint, answer) in [
            ("fk", api::fk(model, body)),
            ("ik", api::ik(model, body)),
            ("collide", api::collide(model, Ok(cmodel), body)),
        ] {
            match answer {
                Ok(v) => {
                    assert_no_null_numbers(&v, endpoint, body);
                    ok += 1;
                }
                Err(e) => {
                    assert_eq!(e.status, 400, "{}", String::from_utf8_lossy(body));
                    assert!(!e.message.is_empty());
                    bad += 1;
                }
            }
        }
    }
    // Both outcomes are exercised, not only the refusals.
    assert!(ok > 100 && bad > 100, "{ok} answers, {bad} refusals");
}

/// The viewer finds a relative mesh name by the rule of every command: next to the model file
/// first, then in the `--mesh-path` directories.
#[test]
fn relative_meshes_are_found_next_to_the_model_before_the_mesh_paths() {
    let root = std::env::temp_dir().join(format!("kinetree-view-meshes-{}", std::process::id()));
    let (model_dir, other) = (root.join("model"), root.join("other"));
    for dir in [&model_dir, &other] {
        std::fs::create_dir_all(dir.join("meshes")).unwrap();
        std::fs::write(
            dir.join("meshes/cube.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )
        .unwrap();
    }
    let urdf = model_dir.join("robot.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="cube"><link name="a"><visual><geometry><mesh filename="meshes/cube.obj"/></geometry></visual></link></robot>"#,
    )
    .unwrap();
    let found = |mesh_paths: Vec<PathBuf>| {
        let state = State::new(&Args {
            model: urdf.clone(),
            mesh_paths,
            no_open: true,
            ..Args::default()
        })
        .unwrap();
        let files: Vec<PathBuf> = state.mesh_files.values().cloned().collect();
        files
    };
    let own = model_dir.join("meshes/cube.obj").canonicalize().unwrap();
    let theirs = other.join("meshes/cube.obj").canonicalize().unwrap();
    assert_eq!(found(vec![other.clone()]), [own]);
    std::fs::remove_file(model_dir.join("meshes/cube.obj")).unwrap();
    assert_eq!(found(vec![other.clone()]), [theirs]);
    assert!(found(Vec::new()).is_empty());
    std::fs::remove_dir_all(&root).unwrap();
}
