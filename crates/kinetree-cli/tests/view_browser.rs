//! `kinetree view` in a real browser: headless Chromium driven through chromedriver's W3C
//! WebDriver HTTP API (a few raw HTTP calls, no client crate).
//!
//! Needs Debian's `chromium` and `chromium-driver` (`.ci/run` installs them). Without them the
//! tests fail and say how to install them; `KINETREE_SKIP_BROWSER_TESTS=1` skips them, loudly.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const WIDTH: u32 = 1000;
const HEIGHT: u32 = 700;

fn panda() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/robots/panda.urdf")
}

/// The Chromium and chromedriver executables, or `None` when skipping is asked for.
fn browser() -> Option<(PathBuf, PathBuf)> {
    let find = |names: &[&str]| {
        names.iter().find_map(|n| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|d| d.join(n))
                    .find(|p| p.is_file())
            })
        })
    };
    let chromium = find(&["chromium", "chromium-browser", "google-chrome"]);
    let driver = find(&["chromedriver"]);
    match (chromium, driver) {
        (Some(c), Some(d)) => Some((c, d)),
        _ if std::env::var_os("KINETREE_SKIP_BROWSER_TESTS").is_some() => {
            eprintln!(
                "\n!!! KINETREE_SKIP_BROWSER_TESTS is set: the browser tests of `kinetree view` \
                 did NOT run (Chromium or chromedriver is missing) !!!\n"
            );
            None
        }
        _ => panic!(
            "the browser tests of `kinetree view` need Chromium and chromedriver: \
             `apt-get install chromium chromium-driver` (Debian/Ubuntu; .ci/run does it), or set \
             KINETREE_SKIP_BROWSER_TESTS=1 to skip them"
        ),
    }
}

/// A child process killed when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// One HTTP request with a JSON body on a fresh connection; the JSON answer. A connection that
/// fails (refused, reset or closed early: chromedriver under a loaded machine does this now and
/// then) is retried on a new connection a few times before the test fails with the last error.
fn request(port: u16, method: &str, path: &str, body: Option<&Value>) -> Value {
    let body = body.map(Value::to_string).unwrap_or_default();
    let mut last = String::new();
    for attempt in 0..4 {
        if attempt > 0 {
            std::thread::sleep(Duration::from_millis(250 << attempt));
        }
        match try_request(port, method, path, &body) {
            Ok(answer) => return answer,
            Err(e) => last = e.to_string(),
        }
    }
    panic!("{method} {path}: {last} (4 attempts)")
}

/// One attempt of [`request`]: an I/O error, a connection closed early or an unreadable answer
/// is an `Err`.
fn try_request(port: u16, method: &str, path: &str, body: &str) -> std::io::Result<Value> {
    use std::io::{Error, ErrorKind};
    let mut s = TcpStream::connect(("127.0.0.1", port))?;
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )?;
    let closed = |what: &str| {
        Error::new(
            ErrorKind::UnexpectedEof,
            format!("connection closed {what}"),
        )
    };
    // chromedriver keeps the connection open: read the head, then Content-Length bytes.
    let mut out = Vec::new();
    let mut buf = [0u8; 65536];
    let end = loop {
        if let Some(end) = out.windows(4).position(|w| w == b"\r\n\r\n") {
            break end;
        }
        let n = s.read(&mut buf)?;
        if n == 0 {
            return Err(closed("before the head"));
        }
        out.extend_from_slice(&buf[..n]);
    };
    let head = String::from_utf8_lossy(&out[..end]).to_ascii_lowercase();
    let mut rest = out[end + 4..].to_vec();
    let length = head
        .lines()
        .find_map(|l| l.strip_prefix("content-length:"))
        .map(|v| v.trim().parse::<usize>().unwrap());
    if let Some(length) = length {
        while rest.len() < length {
            let n = s.read(&mut buf)?;
            if n == 0 {
                return Err(closed("in the body"));
            }
            rest.extend_from_slice(&buf[..n]);
        }
    } else {
        s.read_to_end(&mut rest)?;
        if head.contains("transfer-encoding: chunked") {
            rest = dechunk(&rest);
        }
    }
    serde_json::from_slice(&rest).map_err(|e| {
        Error::new(
            ErrorKind::InvalidData,
            format!("{e}: {}", String::from_utf8_lossy(&rest)),
        )
    })
}

fn dechunk(mut data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = data.windows(2).position(|w| w == b"\r\n").unwrap();
        let size =
            usize::from_str_radix(std::str::from_utf8(&data[..line_end]).unwrap().trim(), 16)
                .unwrap();
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&data[line_end + 2..line_end + 2 + size]);
        data = &data[line_end + 4 + size..];
    }
}

/// A WebDriver session on a headless Chromium.
struct Session {
    port: u16,
    id: String,
    _driver: Killed,
    _profile: PathBuf,
}

impl Session {
    fn new(name: &str) -> Option<Self> {
        let (chromium, chromedriver) = browser()?;
        let port = free_port();
        let driver = Killed(
            Command::new(chromedriver)
                .arg(format!("--port={port}"))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("chromedriver starts"),
        );
        let start = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "chromedriver did not start"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        let profile = std::env::temp_dir().join(format!(
            "kinetree-view-chromium-{}-{name}",
            std::process::id()
        ));
        let args = [
            "--headless".to_string(),
            "--no-sandbox".to_string(),
            "--use-gl=swiftshader".to_string(),
            "--enable-unsafe-swiftshader".to_string(),
            "--disable-background-networking".to_string(),
            "--disable-component-update".to_string(),
            "--disable-sync".to_string(),
            "--no-first-run".to_string(),
            "--disable-dev-shm-usage".to_string(),
            "--force-device-scale-factor=1".to_string(),
            format!("--window-size={WIDTH},{HEIGHT}"),
            format!("--user-data-dir={}", profile.display()),
        ];
        let caps = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": chromium, "args": args},
        }}});
        let answer = request(port, "POST", "/session", Some(&caps));
        let id = answer["value"]["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no session: {answer}"))
            .to_string();
        Some(Self {
            port,
            id,
            _driver: driver,
            _profile: profile,
        })
    }

    fn call(&self, method: &str, path: &str, body: Option<&Value>) -> Value {
        let answer = request(
            self.port,
            method,
            &format!("/session/{}{path}", self.id),
            body,
        );
        assert!(
            answer["value"].get("error").is_none(),
            "{method} {path}: {answer}"
        );
        answer["value"].clone()
    }

    fn go(&self, url: &str) {
        self.call("POST", "/url", Some(&json!({ "url": url })));
    }

    fn script(&self, code: &str) -> Value {
        self.call(
            "POST",
            "/execute/sync",
            Some(&json!({"script": code, "args": []})),
        )
    }

    /// Waits until `condition` (a JS expression) is true.
    fn wait_for(&self, condition: &str, what: &str) {
        let start = Instant::now();
        loop {
            if self.script(&format!("return !!({condition});")) == json!(true) {
                return;
            }
            let status = self.script("return document.getElementById('status').textContent;");
            assert!(
                start.elapsed() < Duration::from_secs(120),
                "timed out waiting for {what}; page status: {status}"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    fn screenshot(&self) -> Image {
        let b64 = self.call("GET", "/screenshot", None);
        let png = base64_decode(b64.as_str().unwrap());
        // `KINETREE_VIEW_SCREENSHOT=dir` keeps the pictures (the README's comes from here).
        if let Some(dir) = std::env::var_os("KINETREE_VIEW_SCREENSHOT") {
            let n = std::fs::read_dir(&dir).map_or(0, Iterator::count);
            std::fs::write(Path::new(&dir).join(format!("shot-{n}.png")), &png).unwrap();
        }
        Image::from_png(&png)
    }

    /// A link's origin on the screen (page pixels).
    fn project(&self, link: &str) -> (f64, f64) {
        let p = self.script(&format!("return kinetreeProject('{link}');"));
        (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let _ = request(self.port, "DELETE", &format!("/session/{}", self.id), None);
        let _ = std::fs::remove_dir_all(&self._profile);
    }
}

struct Image {
    width: usize,
    height: usize,
    rgba: Vec<u8>,
}

impl Image {
    fn from_png(bytes: &[u8]) -> Self {
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.color_type.samples();
        let rgba = buf[..info.buffer_size()]
            .chunks(channels)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        Self {
            width: info.width as usize,
            height: info.height as usize,
            rgba,
        }
    }

    /// Robot-coloured: saturated (the background, the grid and the panel are greys; the robot's
    /// fallback colour is blue and colliding links are red).
    fn is_robot(&self, x: usize, y: usize) -> bool {
        let p = &self.rgba[4 * (y * self.width + x)..][..3];
        let max = p.iter().max().unwrap();
        let min = p.iter().min().unwrap();
        max - min > 60
    }

    /// How many robot pixels within `r` pixels of `c`.
    fn robot_near(&self, c: (f64, f64), r: usize) -> usize {
        let (cx, cy) = (c.0.round() as usize, c.1.round() as usize);
        let mut n = 0;
        for y in cy.saturating_sub(r)..(cy + r + 1).min(self.height) {
            for x in cx.saturating_sub(r)..(cx + r + 1).min(self.width) {
                n += usize::from(self.is_robot(x, y));
            }
        }
        n
    }

    fn robot_total(&self, x0: usize) -> usize {
        (0..self.height)
            .flat_map(|y| (x0..self.width).map(move |x| (x, y)))
            .filter(|&(x, y)| self.is_robot(x, y))
            .count()
    }

    /// Pixels within `r` of `c` that differ between two screenshots.
    fn differing_near(&self, other: &Image, c: (f64, f64), r: usize) -> usize {
        let (cx, cy) = (c.0.round() as usize, c.1.round() as usize);
        let mut n = 0;
        for y in cy.saturating_sub(r)..(cy + r + 1).min(self.height) {
            for x in cx.saturating_sub(r)..(cx + r + 1).min(self.width) {
                let i = 4 * (y * self.width + x);
                let d: u32 = (0..3)
                    .map(|k| u32::from(self.rgba[i + k].abs_diff(other.rgba[i + k])))
                    .sum();
                n += usize::from(d > 60);
            }
        }
        n
    }
}

fn base64_decode(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let digits: Vec<u8> = s
        .bytes()
        .filter(|&c| c != b'=' && !c.is_ascii_whitespace())
        .map(value)
        .collect();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &d)| n | (u32::from(d) << (18 - 6 * i)));
        for k in 0..chunk.len() - 1 {
            out.push((n >> (16 - 8 * k)) as u8);
        }
    }
    out
}

/// `kinetree view panda.urdf --no-open --port 0`; the URL it prints.
fn serve(extra: &[&str]) -> (Killed, String) {
    serve_model(&panda(), extra)
}

/// `kinetree view MODEL --no-open EXTRA…`, and the URL it serves.
fn serve_model(model: &Path, extra: &[&str]) -> (Killed, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .arg("view")
        .arg(model)
        .args(["--no-open"])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://127.0.0.1:"))
        .unwrap_or_else(|| panic!("no URL in {line:?}"))
        .to_string();
    (Killed(child), url)
}

/// Robot pixels around the origins of links that sit inside the Panda's meshes.
fn assert_robot_drawn(session: &Session, image: &Image) {
    assert_eq!(image.width, WIDTH as usize);
    // The panel (300 px) has no robot; the 3D view does.
    let total = image.robot_total(300);
    assert!(total > 5000, "only {total} robot-coloured pixels");
    for link in ["panda_link0", "panda_link2", "panda_link4", "panda_hand"] {
        let c = session.project(link);
        let n = image.robot_near(c, 6);
        assert!(
            n >= 100,
            "{link} at {c:?}: {n} of 169 pixels robot-coloured"
        );
    }
    // A corner of the view far from the robot is background.
    assert_eq!(image.robot_near((f64::from(WIDTH) - 20.0, 20.0), 10), 0);
}

#[test]
fn the_page_shows_the_panda_and_a_slider_moves_it() {
    let Some(session) = Session::new("serve") else {
        return;
    };
    let (_server, url) = serve(&[]);
    session.go(&url);
    session.wait_for(
        "document.body.dataset.ready === 'true' && kinetree.ready",
        "the robot",
    );
    let before = session.screenshot();
    assert_robot_drawn(&session, &before);
    let hand_before = session.project("panda_hand");

    // Focus panda_joint2's slider and press End: the slider goes to the joint's upper limit
    // (1.7628 rad), as a keyboard user would do it.
    let slider = session.call(
        "POST",
        "/element",
        Some(&json!({"using": "css selector", "value": "input[data-joint='panda_joint2']"})),
    );
    let element = slider.as_object().unwrap().values().next().unwrap().clone();
    session.call(
        "POST",
        &format!("/element/{}/value", element.as_str().unwrap()),
        Some(&json!({"text": "\u{E010}"})),
    );
    session.wait_for("kinetree.q[1] > 1.5 && !kinetree.busy", "the new pose");
    let after = session.screenshot();
    let hand_after = session.project("panda_hand");
    let moved =
        ((hand_after.0 - hand_before.0).powi(2) + (hand_after.1 - hand_before.1).powi(2)).sqrt();
    assert!(moved > 50.0, "the hand moved {moved} px on the screen");
    // Where the hand was and where it is now, the pictures differ; the base has not moved.
    for c in [hand_before, hand_after] {
        let n = after.differing_near(&before, c, 10);
        assert!(n > 100, "around {c:?}: {n} of 441 pixels differ");
    }
    assert!(after.robot_near(hand_after, 6) >= 100);
    let base = session.project("panda_link0");
    assert!(after.differing_near(&before, base, 10) < 20);
}

#[test]
fn the_exported_html_renders_from_file_with_the_network_off() {
    let Some(session) = Session::new("export") else {
        return;
    };
    let file = std::env::temp_dir().join(format!("kinetree-view-{}.html", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .arg("view")
        .arg(panda())
        .args(["--q", "panda_joint1=0.5", "--export"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    session.call(
        "POST",
        "/chromium/network_conditions",
        Some(
            &json!({"network_conditions": {"offline": true, "latency": 0,
            "download_throughput": 0, "upload_throughput": 0}}),
        ),
    );
    session.go(&format!("file://{}", file.display()));
    session.wait_for(
        "document.body.dataset.ready === 'true'",
        "the exported robot",
    );
    // The pose embedded is the one asked for.
    assert_eq!(session.script("return kinetree.q[0];"), json!(0.5));
    let image = session.screenshot();
    assert_robot_drawn(&session, &image);
    std::fs::remove_file(&file).unwrap();
}

/// A leg whose hip is a composite joint (two rotations) and whose knee is a revolute joint.
const LEG: &str = r#"{"name": "leg",
  "links": [
    {"name": "pelvis", "visuals": [{"geometry": {"type": "box", "size": [0.2, 0.2, 0.1]}}]},
    {"name": "thigh", "inertial": {"origin": {"xyz": [0, 0, -0.2]}, "mass": 1.5,
       "inertia": {"ixx": 0.03, "iyy": 0.04, "izz": 0.02}},
     "visuals": [{"origin": {"xyz": [0, 0, -0.2]}, "geometry": {"type": "box", "size": [0.05, 0.05, 0.4]}}]},
    {"name": "shank", "inertial": {"origin": {"xyz": [0, 0, -0.2]}, "mass": 1.0,
       "inertia": {"ixx": 0.03, "iyy": 0.04, "izz": 0.02}},
     "visuals": [{"origin": {"xyz": [0, 0, -0.2]}, "geometry": {"type": "box", "size": [0.05, 0.05, 0.4]}}]}],
  "joints": [
    {"name": "hip", "type": "composite", "parent": "pelvis", "child": "thigh",
     "factors": [{"param": "ry", "limits": {"lower": -1, "upper": 1}},
                 {"param": "rx", "limits": {"lower": -1, "upper": 1}}]},
    {"name": "knee", "type": "revolute", "parent": "thigh", "child": "shank",
     "origin": {"xyz": [0, 0, -0.4]}, "axis": [0, 1, 0], "limits": {"lower": 0, "upper": 2}}]}"#;

#[test]
fn a_composite_joint_has_a_slider_per_variable_and_no_virtual_link_is_an_ik_target() {
    let Some(session) = Session::new("composite") else {
        return;
    };
    let model = std::env::temp_dir().join(format!("kinetree-view-leg-{}.json", std::process::id()));
    std::fs::write(&model, LEG).unwrap();
    let (_server, url) = serve_model(&model, &[]);
    session.go(&url);
    session.wait_for(
        "document.body.dataset.ready === 'true' && kinetree.ready",
        "the leg",
    );
    let options = session.script(
        "return Array.from(document.querySelectorAll('#ik-frame option')).map((o) => o.textContent);",
    );
    assert_eq!(options, json!(["pelvis", "thigh", "shank"]));
    let sliders = session.script(
        "return Array.from(document.querySelectorAll('#joints input[type=range]')).map((e) => e.dataset.joint);",
    );
    assert_eq!(sliders, json!(["hip.ry", "hip.rx", "knee"]));
    let _ = std::fs::remove_file(&model);
}
