//! The server against hostile clients (issue #39, items 1–6): each attack on the live server on
//! loopback, then a correct `/api/fk`.

use super::*;

/// What a raw client got: the bytes read, and whether the server closed the connection (rather
/// than the read timing out).
fn read_until_closed(s: &mut TcpStream, timeout: Duration) -> (Vec<u8>, bool) {
    s.set_read_timeout(Some(timeout)).unwrap();
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        match s.read(&mut buf) {
            Ok(0) => return (out, true),
            Ok(n) => out.extend_from_slice(&buf[..n]),
            // A reset is a close too (the server closed with unread bytes).
            Err(e) if e.kind() == std::io::ErrorKind::ConnectionReset => return (out, true),
            Err(_) => return (out, false),
        }
    }
}

/// The status code of the response at the start of `bytes`, if there is one.
fn status_of(bytes: &[u8]) -> Option<u16> {
    let text = String::from_utf8_lossy(bytes);
    text.strip_prefix("HTTP/1.1 ")?.get(..3)?.parse().ok()
}

/// A correct `/api/fk` answers within 5 s, equal to the library.
fn assert_fk_answers(port: u16, model: &Model) {
    let start = Instant::now();
    let mut q = kinetree::kinematics::configuration::neutral_configuration(model);
    q[0] = 0.3;
    let (status, answer) = post_json(port, "/api/fk", &json!({ "q": q }));
    assert_eq!(status, 200, "{answer}");
    assert_links_equal(&answer, &library_links(model, &q));
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "{:?}",
        start.elapsed()
    );
}

/// Issue #39, item 1: a declared Content-Length is never allocated. 1e14 bytes gets 413 (it
/// aborted the process), u64::MAX gets 431 (it panicked a worker: five of them left none),
/// and a GET's declared body is never read; a head over the limit gets 431.
#[test]
fn huge_declared_bodies_are_refused_before_allocation_and_the_server_keeps_serving() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    let cases = [
        ("POST /api/fk", "100000000000000", 413),
        ("POST /api/ik", "18446744073709551615", 431),
        ("GET /", "100000000000000", 200),
    ];
    for (request, length, status) in cases {
        for _ in 0..5 {
            let mut s = raw_client(port);
            let head = format!(
                "{request} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: {length}\r\n\r\n"
            );
            s.write_all(head.as_bytes()).unwrap();
            let (answer, closed) = read_until_closed(&mut s, Duration::from_secs(5));
            assert_eq!(status_of(&answer), Some(status), "{request} {length}");
            // The rest of the declared body is never waited for.
            assert!(closed, "{request} {length}: the connection stays open");
        }
        assert_fk_answers(port, &state.model);
    }
    let mut s = raw_client(port);
    let long = "x".repeat(server::MAX_HEADER_BYTES);
    let head = format!("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Long: {long}\r\n\r\n");
    // The server may answer and close before the end of the head: ignore a write error.
    let _ = s.write_all(head.as_bytes());
    let (answer, _) = read_until_closed(&mut s, Duration::from_secs(5));
    assert_eq!(status_of(&answer), Some(431));
    assert_fk_answers(port, &state.model);
    running.stop();
}

/// Issue #39, item 2: clients that send a head and stall (a partial body, a partial chunked
/// body, a 413 left unread, a partial head), more of them than the old four workers, do not
/// stop the page; the stalled body gets 408 and the stalled head is closed, each within its
/// deadline.
#[test]
fn stalled_clients_do_not_block_the_server_and_time_out() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    let stalls = [
        "POST /api/fk HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100\r\n\r\n{\"q\": [",
        "POST /api/fk HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n5\r\n{\"q\":\r\n",
        "POST /api/ik HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 2000000\r\n\r\n",
        "GET / HTTP/1.1\r\nHost: 127",
    ];
    let start = Instant::now();
    let mut clients: Vec<TcpStream> = (0..2)
        .flat_map(|_| stalls)
        .map(|stall| {
            let mut s = raw_client(port);
            s.write_all(stall.as_bytes()).unwrap();
            s
        })
        .collect();
    assert_fk_answers(port, &state.model);
    // Each stalled client is answered and closed within its deadline (with a margin).
    let expected = [Some(408), Some(408), Some(413), None];
    for (k, s) in clients.iter_mut().enumerate() {
        let (answer, closed) = read_until_closed(s, Duration::from_secs(20));
        assert_eq!(status_of(&answer), expected[k % 4], "client {k}");
        assert!(closed, "client {k} is still open");
    }
    let limit = server::BODY_TIMEOUT.max(server::HEADER_TIMEOUT) + Duration::from_secs(5);
    assert!(start.elapsed() < limit, "{:?}", start.elapsed());
    assert_fk_answers(port, &state.model);
    running.stop();
}

/// Issue #39, item 3: an `HTTP/2.0` request line (and HTTP/2's connection preface) is refused
/// and closed at once, leaving nothing behind.
#[test]
fn other_http_versions_are_refused_and_closed_at_once() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    for request in [
        "GET / HTTP/2.0\r\nHost: 127.0.0.1\r\n\r\n",
        "GET / HTTP/1.2\r\nHost: 127.0.0.1\r\n\r\n",
        "PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n",
    ] {
        for _ in 0..5 {
            let start = Instant::now();
            let mut s = raw_client(port);
            s.write_all(request.as_bytes()).unwrap();
            let (answer, closed) = read_until_closed(&mut s, Duration::from_secs(5));
            assert!(closed, "{request:?} is left open");
            assert!(start.elapsed() < Duration::from_secs(2), "{request:?}");
            // hyper answers 400 where it can parse a request line at all.
            if !request.starts_with("PRI") {
                assert_eq!(status_of(&answer), Some(400), "{request:?}");
            }
        }
    }
    assert_fk_answers(port, &state.model);
    running.stop();
}

/// One GET with the given `Host` header line (none when empty): the status.
fn get_with_host(port: u16, path: &str, host_line: &str) -> u16 {
    let mut s = raw_client(port);
    write!(
        s,
        "GET {path} HTTP/1.1\r\n{host_line}Connection: close\r\n\r\n"
    )
    .unwrap();
    let (answer, _) = read_until_closed(&mut s, Duration::from_secs(5));
    status_of(&answer).unwrap_or_else(|| panic!("no answer for {host_line:?}"))
}

/// Issue #39, item 4: a page of another site that rebinds its name to 127.0.0.1 sends its own
/// name as `Host`, and gets 403 from every path; this machine's names (any port) and the
/// `--bind` address are answered.
#[test]
fn requests_for_another_host_are_refused() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    for host in [
        "Host: evil.example\r\n",
        &format!("Host: evil.example:{port}\r\n"),
        "Host: localhost.evil.example\r\n",
        "Host: 127.0.0.1.nip.io\r\n",
        "Host: 127.0.0.2\r\n",
        "Host: 127.0.0.1:x\r\n",
        "Host: [::1\r\n",
        "",
    ] {
        for path in ["/", "/api/model", "/meshes/0/x.stl"] {
            assert_eq!(get_with_host(port, path, host), 403, "{host:?} {path}");
        }
    }
    // An absolute URL naming another site is refused too, whatever the Host says.
    let mut s = raw_client(port);
    s.write_all(b"GET http://evil.example/api/model HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
        .unwrap();
    let (answer, _) = read_until_closed(&mut s, Duration::from_secs(5));
    assert_eq!(status_of(&answer), Some(403));
    let (status, body) = http(port, "POST", "/api/fk", b"{}");
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    for host in [
        "Host: 127.0.0.1\r\n".to_string(),
        format!("Host: 127.0.0.1:{port}\r\n"),
        format!("Host: LOCALHOST:{port}\r\n"),
        "Host: localhost\r\n".to_string(),
        "Host: [::1]:8080\r\n".to_string(),
    ] {
        assert_eq!(get_with_host(port, "/api/model", &host), 200, "{host:?}");
    }
    running.stop();
    // `--bind 0.0.0.0` answers any address (to reach it from another machine) but no name
    // other than localhost.
    let any = server::start(Arc::clone(&state), "0.0.0.0", 0, 1).unwrap();
    for (host, status) in [
        ("Host: 192.168.1.20:8000\r\n", 200),
        ("Host: [fe80::1]\r\n", 200),
        ("Host: 0.0.0.0\r\n", 200),
        ("Host: localhost\r\n", 200),
        ("Host: evil.example\r\n", 403),
    ] {
        assert_eq!(
            get_with_host(any.port, "/api/model", host),
            status,
            "{host:?}"
        );
    }
    any.stop();
}

/// Issue #39, item 5: the server serves exactly the mesh files the model references (however
/// their URL is percent-encoded), and nothing else of the directories they are in.
#[test]
fn only_the_meshes_the_model_references_are_served() {
    let root = std::env::temp_dir().join(format!("kinetree-view-only-{}", std::process::id()));
    std::fs::create_dir_all(root.join("meshes")).unwrap();
    let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(root.join("meshes/cube.obj"), cube).unwrap();
    std::fs::write(root.join("meshes/other.obj"), cube).unwrap();
    std::fs::write(root.join("meshes/notes.txt"), "secret").unwrap();
    let urdf = root.join("robot.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="cube"><link name="a"><visual><geometry><mesh filename="meshes/cube.obj"/></geometry></visual></link></robot>"#,
    )
    .unwrap();
    let (running, _) = serve(&Args {
        model: urdf,
        no_open: true,
        ..Args::default()
    });
    let port = running.port;
    let (status, bytes) = http(port, "GET", "/api/model", b"");
    assert_eq!(status, 200);
    let model: Value = serde_json::from_slice(&bytes).unwrap();
    let url = model["links"][0]["visuals"][0]["geometry"]["url"]
        .as_str()
        .unwrap();
    assert_eq!(url, "/meshes/0/meshes/cube.obj");
    for path in [
        url,
        "/meshes/0/meshes/cub%65.obj",
        "/meshes/0/%6Deshes/cube.obj",
    ] {
        let (status, bytes) = http(port, "GET", path, b"");
        assert_eq!(status, 200, "{path}");
        assert_eq!(bytes, cube.as_bytes(), "{path}");
    }
    for path in [
        "/meshes/0/meshes/other.obj",
        "/meshes/0/meshes/notes.txt",
        "/meshes/0/robot.urdf",
        "/meshes/0/meshes/../robot.urdf",
        "/meshes/0/meshes%2Fcube.obj",
        "/meshes/1/meshes/cube.obj",
        "/meshes/0/meshes/cube.obj/",
        "/meshes/0/meshes/%ZZ",
    ] {
        let (status, bytes) = http(port, "GET", path, b"");
        let text = String::from_utf8_lossy(&bytes);
        assert_eq!(status, 404, "{path}: {text}");
        assert!(text.contains("no such mesh"), "{path}: {text}");
    }
    running.stop();
    std::fs::remove_dir_all(&root).unwrap();
}

/// Issue #39, item 6: link and joint names are escaped for the export's inline script, so a
/// name like `<!--<script>` or `</script><script>…` cannot change how the page is parsed.
#[test]
fn the_export_escapes_names_for_the_script_element() {
    let root = std::env::temp_dir().join(format!("kinetree-view-escape-{}", std::process::id()));
    std::fs::create_dir_all(&root).unwrap();
    let names = [
        "<!--<script>",
        "</script><script>alert(1)</script>",
        "a&b\u{2028}c\u{2029}d",
    ];
    let urdf_of = |names: [&str; 3]| {
        let escape = |n: &str| {
            n.replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('>', "&gt;")
        };
        let [a, b, c] = names.map(escape);
        format!(
            r#"<robot name="{a}"><link name="{a}"/><link name="{b}"/>
            <joint name="{c}" type="revolute"><parent link="{a}"/><child link="{b}"/>
            <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
        )
    };
    let export = |file: &str, names: [&str; 3]| {
        let urdf = root.join(file);
        std::fs::write(&urdf, urdf_of(names)).unwrap();
        let state = State::new(&Args {
            model: urdf,
            ..panda_args()
        })
        .unwrap();
        super::super::page::export_html(&state).unwrap()
    };
    let hostile = export("hostile.urdf", names);
    let plain = export("plain.urdf", ["a", "b", "c"]);
    // The hostile names add no tag, comment or script to the page.
    for pattern in ["<script", "</script", "<!--"] {
        assert_eq!(
            hostile.matches(pattern).count(),
            plain.matches(pattern).count(),
            "{pattern}"
        );
    }
    let start = "window.KINETREE_EMBED = ";
    let embed = &hostile[hostile.find(start).unwrap() + start.len()..];
    let embed = &embed[..embed.find(";</script>").unwrap()];
    for c in ['<', '>', '&', '\u{2028}', '\u{2029}'] {
        assert!(!embed.contains(c), "{c:?} in the inline script");
    }
    // The names are still the same JSON strings.
    let value: Value = serde_json::from_str(embed).unwrap();
    let links = value["model"]["links"].as_array().unwrap();
    assert_eq!(links[0]["name"], names[0]);
    assert_eq!(links[1]["name"], names[1]);
    assert_eq!(value["model"]["joints"][0]["name"], names[2]);
    std::fs::remove_dir_all(&root).unwrap();
}

/// Issue #39, item 6: the API refuses a configuration as `kinetree compute` does (the library's
/// checks), rather than answering for fingers at 1e308 m or a quaternion of norm 2, then keeps
/// serving.
#[test]
fn the_api_refuses_states_the_library_refuses() {
    let (running, state) = serve(&panda_args());
    let port = running.port;
    let far = json!({"panda_finger_joint1": 1e308});
    for (path, body) in [
        ("/api/fk", json!({ "q": far })),
        ("/api/collide", json!({ "q": far })),
        (
            "/api/ik",
            json!({"q": far, "frame": "panda_hand", "target": {"xyz": [0.3, 0, 0.5]}}),
        ),
    ] {
        let (status, answer) = post_json(port, path, &body);
        assert_eq!(status, 400, "{path}: {answer}");
        let message = answer["error"].as_str().unwrap();
        assert!(message.contains("overflowed"), "{path}: {message}");
    }
    // Far, but not past what the library computes: answered.
    let (status, answer) = post_json(
        port,
        "/api/fk",
        &json!({"q": {"panda_finger_joint1": 10.0}}),
    );
    assert_eq!(status, 200, "{answer}");
    assert_fk_answers(port, &state.model);
    running.stop();
    // A floating base's quaternion must have norm 1, as for every library call.
    let (running, state) = serve(&Args {
        floating: true,
        ..panda_args()
    });
    let mut q = kinetree::kinematics::configuration::neutral_configuration(&state.model);
    q[6] = 2.0;
    let (status, answer) = post_json(running.port, "/api/fk", &json!({ "q": q }));
    assert_eq!(status, 400, "{answer}");
    let message = answer["error"].as_str().unwrap();
    assert!(message.contains("norm 2"), "{message}");
    assert_fk_answers(running.port, &state.model);
    running.stop();
}
