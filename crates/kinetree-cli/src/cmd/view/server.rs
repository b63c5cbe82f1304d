//! The HTTP side of `kinetree view`: connections and their limits, the Host check, routing and
//! the mesh files.
//!
//! One thread runs a tokio current-thread runtime that accepts connections and speaks HTTP/1.1
//! through hyper; the API's computations and the file reads run on at most `threads` blocking
//! threads, so a slow computation never stalls the sockets. What a client declares is never
//! allocated before it is checked, and no client can hold the server:
//!
//! - at most [`MAX_CONNECTIONS`] connections are served at once (the next ones wait in the
//!   listen queue until one closes);
//! - a request's head must arrive within [`HEADER_TIMEOUT`] and fit in [`MAX_HEADER_BYTES`]
//!   (431 otherwise), which also closes a keep-alive connection idle for that long;
//! - a body over [`MAX_BODY`] gets 413 from its `Content-Length` before any of it is read, or
//!   as soon as a chunked body passes the limit, and a body must arrive within
//!   [`BODY_TIMEOUT`] (408); both answers close the connection;
//! - a request is answered within [`REQUEST_DEADLINE`] (503 otherwise);
//! - a connection serves at most [`MAX_REQUESTS_PER_CONNECTION`] requests and lives at most
//!   [`MAX_CONNECTION_AGE`], then closes once its request under way is answered;
//! - only HTTP/1.0 and HTTP/1.1 are spoken: hyper answers another version (`HTTP/2.0`) 400 and
//!   closes;
//! - a request whose `Host` is not this machine's loopback name or the `--bind` address gets
//!   403, so that a page of another site cannot reach the API by DNS rebinding.

use super::State;
use super::api::{self, ApiError};
use super::page;
use http_body_util::{BodyExt, Full, LengthLimitError, Limited};
use hyper::body::{Body as _, Bytes, Incoming};
use hyper::header::{self, HeaderValue};
use hyper::http::request::Parts;
use hyper::server::conn::http1;
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use serde_json::json;
use std::collections::HashMap;
use std::convert::Infallible;
use std::net::{IpAddr, Ipv6Addr};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;
use tokio::sync::{OwnedSemaphorePermit, Semaphore, oneshot};

/// The largest request body accepted (1 MiB); larger ones get 413.
pub(crate) const MAX_BODY: usize = 1 << 20;
/// The largest request head (request line and headers) accepted; larger ones get 431.
pub(crate) const MAX_HEADER_BYTES: usize = 16 << 10;
/// The most header lines in a request.
const MAX_HEADERS: usize = 64;
/// The time a client has to send a request's head (and the longest a keep-alive connection
/// stays idle).
pub(crate) const HEADER_TIMEOUT: Duration = Duration::from_secs(10);
/// The time a client has to send a request's body once its head has arrived.
pub(crate) const BODY_TIMEOUT: Duration = Duration::from_secs(10);
/// The time a request has, from its head to its answer.
pub(crate) const REQUEST_DEADLINE: Duration = Duration::from_secs(30);
/// The most connections served at once.
pub(crate) const MAX_CONNECTIONS: usize = 64;
/// The most requests one connection serves before the server closes it.
pub(crate) const MAX_REQUESTS_PER_CONNECTION: usize = 1000;
/// The longest a connection lives; then it closes once its request under way is answered.
pub(crate) const MAX_CONNECTION_AGE: Duration = Duration::from_secs(120);
/// The time a connection has to finish its request under way when it has lived too long.
const CLOSE_GRACE: Duration = Duration::from_secs(5);

/// A running server: its port, and the thread to join when it stops.
pub(crate) struct Running {
    /// Stops the server when sent to (or dropped).
    stop: oneshot::Sender<()>,
    thread: std::thread::JoinHandle<()>,
    /// The port it listens on.
    pub(crate) port: u16,
}

impl std::fmt::Debug for Running {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Running")
            .field("port", &self.port)
            .finish_non_exhaustive()
    }
}

impl Running {
    /// Blocks until the server stops (never, unless [`Running::stop`] is called elsewhere; the
    /// command ends with Ctrl-C, whose default action ends the process).
    pub(crate) fn join(self) {
        let Self { stop, thread, .. } = self;
        let _ = thread.join();
        drop(stop);
    }

    /// Stops accepting connections, closes the open ones and joins the server's thread.
    #[cfg(test)]
    pub(crate) fn stop(self) {
        let _ = self.stop.send(());
        let _ = self.thread.join();
    }
}

/// What every connection shares: the state and the Host names answered.
#[derive(Debug)]
struct Site {
    state: Arc<State>,
    hosts: Hosts,
}

/// Binds `bind:port` (port 0 for a free one) and serves `state` with `threads` threads for the
/// computations.
///
/// # Errors
/// The bind error, or a runtime that cannot start.
pub(crate) fn start(
    state: Arc<State>,
    bind: &str,
    port: u16,
    threads: usize,
) -> anyhow::Result<Running> {
    let addr = if bind.contains(':') {
        format!("[{bind}]:{port}")
    } else {
        format!("{bind}:{port}")
    };
    let listener = std::net::TcpListener::bind(&addr)
        .map_err(|e| anyhow::anyhow!("cannot listen on {addr}: {e}"))?;
    listener.set_nonblocking(true)?;
    let port = listener.local_addr()?.port();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .enable_time()
        .max_blocking_threads(threads.max(1))
        .build()?;
    let listener = {
        let _inside = runtime.enter();
        tokio::net::TcpListener::from_std(listener)?
    };
    let site = Arc::new(Site {
        state,
        hosts: Hosts::new(bind),
    });
    let (stop, stopped) = oneshot::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("kinetree-view".to_string())
        .spawn(move || {
            runtime.block_on(async move {
                let accepting = tokio::spawn(accept(listener, site));
                let _ = stopped.await;
                accepting.abort();
            });
            // The open connections end with the runtime; a computation under way may finish.
            runtime.shutdown_timeout(Duration::from_secs(1));
        })?;
    Ok(Running { stop, thread, port })
}

/// Accepts connections, at most [`MAX_CONNECTIONS`] open at once.
async fn accept(listener: tokio::net::TcpListener, site: Arc<Site>) {
    let slots = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    loop {
        let Ok(slot) = Arc::clone(&slots).acquire_owned().await else {
            return;
        };
        match listener.accept().await {
            Ok((stream, _)) => {
                tokio::spawn(connection(stream, Arc::clone(&site), slot));
            }
            // Out of file descriptors, or a connection reset before it was accepted: wait a
            // little rather than spin.
            Err(_) => tokio::time::sleep(Duration::from_millis(50)).await,
        }
    }
}

/// Serves one connection within the limits of the module docs; `_slot` is released at the end.
async fn connection(stream: tokio::net::TcpStream, site: Arc<Site>, _slot: OwnedSemaphorePermit) {
    let _ = stream.set_nodelay(true);
    let served = AtomicUsize::new(0);
    let service = hyper::service::service_fn(move |request| {
        let last = served.fetch_add(1, Ordering::Relaxed) + 1 >= MAX_REQUESTS_PER_CONNECTION;
        respond(Arc::clone(&site), request, last)
    });
    let connection = http1::Builder::new()
        .timer(TokioTimer::new())
        .header_read_timeout(HEADER_TIMEOUT)
        .max_header_size(MAX_HEADER_BYTES)
        .max_headers(MAX_HEADERS)
        .serve_connection(TokioIo::new(stream), service);
    let mut connection = std::pin::pin!(connection);
    // A connection error (a client gone, a malformed request hyper has answered) ends it.
    if tokio::time::timeout(MAX_CONNECTION_AGE, connection.as_mut())
        .await
        .is_err()
    {
        connection.as_mut().graceful_shutdown();
        let _ = tokio::time::timeout(CLOSE_GRACE, connection).await;
    }
}

/// A response body and its content type, or an error.
type Answer = Result<(Vec<u8>, &'static str), ApiError>;

/// Answers one request; `last` closes the connection after it.
async fn respond(
    site: Arc<Site>,
    request: Request<Incoming>,
    last: bool,
) -> Result<Response<Full<Bytes>>, Infallible> {
    let answer = tokio::time::timeout(REQUEST_DEADLINE, answer(site, request))
        .await
        .unwrap_or_else(|_| {
            Err(ApiError {
                status: 503,
                message: format!(
                    "the request took longer than {} s",
                    REQUEST_DEADLINE.as_secs()
                ),
            })
        });
    let (status, body, content_type) = match answer {
        Ok((body, content_type)) => (StatusCode::OK, body, content_type),
        Err(e) => (
            StatusCode::from_u16(e.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR),
            json!({"error": e.message}).to_string().into_bytes(),
            "application/json",
        ),
    };
    let mut response = Response::new(Full::new(Bytes::from(body)));
    *response.status_mut() = status;
    let headers = response.headers_mut();
    headers.insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type));
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    // After a refused or unfinished body the connection is not worth keeping: what is left of
    // the body is never read.
    let refused_body = matches!(status.as_u16(), 408 | 413 | 503);
    if last || refused_body {
        headers.insert(header::CONNECTION, HeaderValue::from_static("close"));
    }
    Ok(response)
}

/// Checks the Host, reads the body of an API call, then routes on a blocking thread.
async fn answer(site: Arc<Site>, request: Request<Incoming>) -> Answer {
    let (parts, body) = request.into_parts();
    site.hosts.check(&parts)?;
    let path = parts.uri.path().to_string();
    let body = match (&parts.method, path.as_str()) {
        (&Method::POST, "/api/fk" | "/api/ik" | "/api/collide") => read_body(body).await?,
        // Other requests' bodies are not read (the connection closes if one was sent).
        _ => Bytes::new(),
    };
    let method = parts.method;
    tokio::task::spawn_blocking(move || route(&site.state, &method, &path, &body))
        .await
        .unwrap_or_else(|_| {
            Err(ApiError {
                status: 500,
                message: "the request failed inside the server".to_string(),
            })
        })
}

fn route(state: &State, method: &Method, path: &str, body: &[u8]) -> Answer {
    let json_answer = |v: Result<serde_json::Value, ApiError>| -> Answer {
        v.map(|v| (v.to_string().into_bytes(), "application/json"))
    };
    match (method, path) {
        (&Method::GET, "/" | "/index.html") => Ok((
            page::index_html(None).into_bytes(),
            "text/html; charset=utf-8",
        )),
        (&Method::GET, "/three.js") => Ok((page::THREE_JS.to_vec(), "text/javascript")),
        (&Method::GET, "/viewer.js") => Ok((page::VIEWER_JS.to_vec(), "text/javascript")),
        (&Method::GET, "/api/model") => json_answer(Ok(state.model_json.clone())),
        (&Method::GET, "/api/trajectory") => json_answer(Ok(state.trajectory.clone())),
        (&Method::GET, "/api/workspace") => state
            .workspace
            .clone()
            .map(|b| (b, "application/octet-stream"))
            .ok_or_else(|| not_found("no workspace was given (--workspace ws.ply)")),
        (&Method::POST, "/api/fk") => json_answer(api::fk(&state.model, body)),
        (&Method::POST, "/api/ik") => json_answer(api::ik(&state.model, body)),
        (&Method::POST, "/api/collide") => json_answer(api::collide(
            &state.model,
            state.collision.as_ref().map_err(String::as_str),
            body,
        )),
        (&Method::GET, p) if p.starts_with("/meshes/") => mesh(&state.mesh_files, p),
        (_, "/api/fk" | "/api/ik" | "/api/collide") => Err(ApiError {
            status: 405,
            message: format!("{path} takes POST"),
        }),
        _ => Err(not_found(&format!("no such page: {path}"))),
    }
}

fn not_found(message: &str) -> ApiError {
    ApiError {
        status: 404,
        message: message.to_string(),
    }
}

/// The request body, at most [`MAX_BODY`] bytes, within [`BODY_TIMEOUT`].
///
/// # Errors
/// 413 past the limit (by the declared length before reading, else as soon as the bytes read
/// pass it), 408 past the deadline, 400 when it cannot be read.
async fn read_body(body: Incoming) -> Result<Bytes, ApiError> {
    let too_large = || ApiError {
        status: 413,
        message: format!("the request body is larger than {MAX_BODY} bytes"),
    };
    // The declared Content-Length, before anything is read or allocated.
    if body.size_hint().lower() > MAX_BODY as u64 {
        return Err(too_large());
    }
    match tokio::time::timeout(BODY_TIMEOUT, Limited::new(body, MAX_BODY).collect()).await {
        Ok(Ok(collected)) => Ok(collected.to_bytes()),
        Ok(Err(e)) if e.is::<LengthLimitError>() => Err(too_large()),
        Ok(Err(e)) => Err(ApiError::bad(format!("cannot read the request body: {e}"))),
        Err(_) => Err(ApiError {
            status: 408,
            message: format!(
                "the request body did not arrive within {} s",
                BODY_TIMEOUT.as_secs()
            ),
        }),
    }
}

/// The Host names the server answers to, as Jupyter's server checks them against DNS
/// rebinding: `127.0.0.1`, `localhost`, `[::1]` and the `--bind` address, with any port. When
/// `--bind` is the unspecified address (`0.0.0.0` or `::`, every interface), any IP address
/// is answered too: a name can be rebound to this machine by another site, an address cannot.
#[derive(Debug)]
struct Hosts {
    /// The `--bind` address as a Host names it (lower case, IPv6 in brackets).
    bind: String,
    /// Whether any IP address is a valid Host.
    any_address: bool,
}

impl Hosts {
    fn new(bind: &str) -> Self {
        let bind = bind.to_ascii_lowercase();
        let any_address = bind.parse::<IpAddr>().is_ok_and(|ip| ip.is_unspecified());
        let bind = if bind.contains(':') {
            format!("[{bind}]")
        } else {
            bind
        };
        Self { bind, any_address }
    }

    /// 403 unless the request's `Host` (and the authority of an absolute URL) is answered.
    fn check(&self, parts: &Parts) -> Result<(), ApiError> {
        let host = parts
            .headers
            .get(header::HOST)
            .and_then(|h| h.to_str().ok());
        let ok = host.is_some_and(|h| self.allows(h))
            && parts
                .uri
                .authority()
                .is_none_or(|a| self.allows(a.as_str()));
        if ok {
            Ok(())
        } else {
            Err(ApiError {
                status: 403,
                message: format!(
                    "this server answers requests for 127.0.0.1, localhost, [::1] and {} only, not for Host {}",
                    self.bind,
                    host.unwrap_or("(none)")
                ),
            })
        }
    }

    /// Whether `host` (`name` or `name:port`) is answered.
    fn allows(&self, host: &str) -> bool {
        let host = host.to_ascii_lowercase();
        let (name, port) = match host.strip_prefix('[') {
            Some(rest) => match rest.split_once(']') {
                Some((ip, port)) => (&host[..ip.len() + 2], port),
                None => return false,
            },
            None => host.split_at(host.find(':').unwrap_or(host.len())),
        };
        let port_ok = port.is_empty()
            || port
                .strip_prefix(':')
                .is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
        let address = || {
            name.parse::<std::net::Ipv4Addr>().is_ok()
                || name
                    .strip_prefix('[')
                    .and_then(|n| n.strip_suffix(']'))
                    .is_some_and(|n| n.parse::<Ipv6Addr>().is_ok())
        };
        port_ok
            && (matches!(name, "127.0.0.1" | "localhost" | "[::1]")
                || name == self.bind
                || (self.any_address && address()))
    }
}

/// `GET /meshes/<k>/<path>`: one of the mesh files the model references (`files`, URL → file,
/// made once at start), whatever percent-encoding the URL uses. Anything else is 404.
fn mesh(files: &HashMap<String, PathBuf>, path: &str) -> Answer {
    let missing = || not_found(&format!("no such mesh: {path}"));
    let segments: Option<Vec<String>> = path
        .split('/')
        .map(|s| percent_decode(s).map(|s| percent_encode(&s)))
        .collect();
    let file = files
        .get(&segments.ok_or_else(missing)?.join("/"))
        .ok_or_else(missing)?;
    let bytes = std::fs::read(file).map_err(|_| missing())?;
    Ok((bytes, page::content_type(file)))
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
