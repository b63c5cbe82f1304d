//! The HTTP side of `kinetree view`: routing, size limits, mesh files, worker threads.

use super::State;
use super::api::{self, ApiError};
use super::page;
use serde_json::json;
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// The largest request body accepted (1 MiB); larger ones get 413.
pub(crate) const MAX_BODY: usize = 1 << 20;

/// A running server: its address, and the workers to join when it stops.
pub(crate) struct Running {
    #[cfg_attr(not(test), expect(dead_code, reason = "only the tests stop a server"))]
    server: Arc<tiny_http::Server>,
    workers: Vec<std::thread::JoinHandle<()>>,
    /// The port it listens on.
    pub(crate) port: u16,
}

impl std::fmt::Debug for Running {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Running")
            .field("port", &self.port)
            .field("workers", &self.workers.len())
            .finish_non_exhaustive()
    }
}

impl Running {
    /// Blocks until every worker ends (never, unless [`Running::stop`] is called elsewhere).
    pub(crate) fn join(self) {
        for w in self.workers {
            let _ = w.join();
        }
    }

    /// Stops accepting requests and joins the workers.
    #[cfg(test)]
    pub(crate) fn stop(self) {
        for _ in &self.workers {
            self.server.unblock();
        }
        self.join();
    }
}

/// Binds `addr` (`host:port`, port 0 for a free one) and serves `state` from `threads` workers.
///
/// # Errors
/// The bind error.
pub(crate) fn start(state: Arc<State>, addr: &str, threads: usize) -> anyhow::Result<Running> {
    let server = tiny_http::Server::http(addr)
        .map_err(|e| anyhow::anyhow!("cannot listen on {addr}: {e}"))?;
    let port = server
        .server_addr()
        .to_ip()
        .map(|a| a.port())
        .ok_or_else(|| anyhow::anyhow!("{addr} is not an IP address"))?;
    let server = Arc::new(server);
    let workers = (0..threads.max(1))
        .map(|_| {
            let server = Arc::clone(&server);
            let state = Arc::clone(&state);
            std::thread::spawn(move || {
                while let Ok(request) = server.recv() {
                    handle(&state, request);
                }
            })
        })
        .collect();
    Ok(Running {
        server,
        workers,
        port,
    })
}

/// A response body and its content type, or an error.
type Answer = Result<(Vec<u8>, &'static str), ApiError>;

fn handle(state: &State, mut request: tiny_http::Request) {
    let method = request.method().clone();
    let url = request
        .url()
        .split('?')
        .next()
        .unwrap_or_default()
        .to_string();
    let answer = route(state, &method, &url, &mut request);
    let response = match answer {
        Ok((body, content_type)) => with_header(
            tiny_http::Response::from_data(body),
            "Content-Type",
            content_type,
        ),
        Err(e) => {
            let body = json!({"error": e.message}).to_string().into_bytes();
            with_header(
                tiny_http::Response::from_data(body).with_status_code(e.status),
                "Content-Type",
                "application/json",
            )
        }
    };
    let response = with_header(response, "Cache-Control", "no-store");
    // A client that went away is not the server's problem.
    let _ = request.respond(response);
}

/// Adds a header (names and values are ASCII chosen here, so it always parses).
fn with_header<R: Read>(
    response: tiny_http::Response<R>,
    name: &str,
    value: &str,
) -> tiny_http::Response<R> {
    match tiny_http::Header::from_bytes(name.as_bytes(), value.as_bytes()) {
        Ok(h) => response.with_header(h),
        Err(()) => response,
    }
}

fn route(
    state: &State,
    method: &tiny_http::Method,
    url: &str,
    request: &mut tiny_http::Request,
) -> Answer {
    use tiny_http::Method::{Get, Post};
    let json_answer = |v: Result<serde_json::Value, ApiError>| -> Answer {
        v.map(|v| (v.to_string().into_bytes(), "application/json"))
    };
    match (method, url) {
        (Get, "/" | "/index.html") => Ok((
            page::index_html(None).into_bytes(),
            "text/html; charset=utf-8",
        )),
        (Get, "/three.js") => Ok((page::THREE_JS.to_vec(), "text/javascript")),
        (Get, "/viewer.js") => Ok((page::VIEWER_JS.to_vec(), "text/javascript")),
        (Get, "/api/model") => json_answer(Ok(state.model_json.clone())),
        (Get, "/api/trajectory") => json_answer(Ok(state.trajectory.clone())),
        (Get, "/api/workspace") => state
            .workspace
            .clone()
            .map(|b| (b, "application/octet-stream"))
            .ok_or_else(|| not_found("no workspace was given (--workspace ws.ply)")),
        (Post, "/api/fk") => json_answer(api::fk(&state.model, &read_body(request)?)),
        (Post, "/api/ik") => json_answer(api::ik(&state.model, &read_body(request)?)),
        (Post, "/api/collide") => json_answer(api::collide(
            &state.model,
            state.collision.as_ref().map_err(String::as_str),
            &read_body(request)?,
        )),
        (Get, u) if u.starts_with("/meshes/") => mesh(&state.mesh_dirs, &u["/meshes/".len()..]),
        (_, "/api/fk" | "/api/ik" | "/api/collide") => Err(ApiError {
            status: 405,
            message: format!("{url} takes POST"),
        }),
        _ => Err(not_found(&format!("no such page: {url}"))),
    }
}

fn not_found(message: &str) -> ApiError {
    ApiError {
        status: 404,
        message: message.to_string(),
    }
}

/// The request body, at most [`MAX_BODY`] bytes.
///
/// # Errors
/// 413 past the limit (by the declared length, before reading), 400 when it cannot be read.
fn read_body(request: &mut tiny_http::Request) -> Result<Vec<u8>, ApiError> {
    let too_large = || ApiError {
        status: 413,
        message: format!("the request body is larger than {MAX_BODY} bytes"),
    };
    if request.body_length().is_some_and(|n| n > MAX_BODY) {
        return Err(too_large());
    }
    let mut body = Vec::new();
    request
        .as_reader()
        .take(MAX_BODY as u64 + 1)
        .read_to_end(&mut body)
        .map_err(|e| ApiError::bad(format!("cannot read the request body: {e}")))?;
    if body.len() > MAX_BODY {
        return Err(too_large());
    }
    Ok(body)
}

/// `GET /meshes/<k>/<path>`: the file `<path>` under the `k`-th mesh directory, only if it is
/// inside it once symlinks are resolved. Anything else (`..`, absolute paths, a symlink that
/// leads out, a missing file) is 404.
fn mesh(dirs: &[PathBuf], rest: &str) -> Answer {
    let missing = || not_found(&format!("no such mesh: /meshes/{rest}"));
    let (k, rel) = rest.split_once('/').ok_or_else(missing)?;
    let dir = k
        .parse::<usize>()
        .ok()
        .and_then(|k| dirs.get(k))
        .ok_or_else(missing)?;
    let rel = percent_decode(rel).ok_or_else(missing)?;
    let rel = Path::new(&rel);
    if rel.components().any(|c| !matches!(c, Component::Normal(_))) {
        return Err(missing());
    }
    let path = dir.join(rel).canonicalize().map_err(|_| missing())?;
    if !path.starts_with(dir) || !path.is_file() {
        return Err(missing());
    }
    let bytes = std::fs::read(&path).map_err(|_| missing())?;
    Ok((bytes, page::content_type(&path)))
}

/// The URL path of `file` (absolute, canonical) under one of `dirs` (canonical), if any.
pub(crate) fn mesh_url(dirs: &[PathBuf], file: &Path) -> Option<String> {
    dirs.iter().enumerate().find_map(|(k, d)| {
        let rel = file.strip_prefix(d).ok()?;
        let parts: Option<Vec<String>> = rel
            .components()
            .map(|c| match c {
                Component::Normal(s) => s.to_str().map(percent_encode),
                _ => None,
            })
            .collect();
        Some(format!("/meshes/{k}/{}", parts?.join("/")))
    })
}

fn percent_encode(s: &str) -> String {
    let mut out = String::new();
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}
