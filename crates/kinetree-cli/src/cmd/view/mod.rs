//! `kinetree view <model>`: a 3D viewer in the browser, served from the command line.
//!
//! The command starts an HTTP/1.1 server (hyper on a tokio current-thread runtime, four threads
//! for the computations; `server.rs` lists its limits and deadlines) bound to 127.0.0.1
//! (another address only with `--bind`, which prints a warning) on a free port (or `--port`),
//! prints the URL and opens the default browser unless `--no-open`. The page is three.js
//! (vendored from the npm package `three` with its licence, compiled into the binary) and
//! never computes kinematics itself: it asks the server. `--export robot.html` writes one
//! self-contained HTML file instead (scripts, meshes and poses inlined) that opens from disk.
//!
//! # The JSON API
//!
//! Configurations (`"q"`) are either an array of `nq` numbers or an object of joint name →
//! value (an array for multi-coordinate joints; unnamed joints stay neutral). Poses are
//! `[x, y, z, qx, qy, qz, qw]` in the world frame (metres, unit quaternion, scalar last).
//!
//! | request | answer |
//! | --- | --- |
//! | `GET /api/model` | `{"name", "nq", "links": [{"name", "parent", "mass", "visuals", "collisions"}], "joints": [{"name", "kind", "q_index", "nq", "lower", "upper", "mimic", "neutral"}], "frames": [names], "initial_q": [nq]}`; visuals and collisions are `{"origin": pose, "geometry": {"type": "box" \| "cylinder" \| "sphere" \| "capsule" \| "mesh", …, "url"}, "color"}` |
//! | `POST /api/fk` `{"q"}` | `{"q", "links": [pose per link], "frames": [pose per frame], "com": [x, y, z]}` |
//! | `POST /api/ik` `{"q", "frame", "target": {"xyz": [3], "quat": [4] (optional)}}` | as `/api/fk` at the solution, plus `"status"` (`converged`, `best_effort`, `failed`), `"position_error"`, `"orientation_error"`, `"iterations"` |
//! | `POST /api/collide` `{"q"}` | `{"available", "pairs": [{"link_a", "link_b", "distance", "colliding"}]}` (signed distances in metres) |
//! | `GET /api/trajectory` | `{"t": [s], "q": [[nq]], "links": [[pose per link]]}` or `null` |
//! | `GET /api/workspace` | the `--workspace` PLY file |
//! | `GET /meshes/<k>/<path>` | a mesh file the model references, found under the `k`-th mesh directory (the URLs of `/api/model`) |
//!
//! Every request must name this machine in its `Host` header (`127.0.0.1`, `localhost` or
//! `[::1]`, or the `--bind` address; any IP address when `--bind` is `0.0.0.0` or `::`), with any
//! port, else it gets 403: a page of another site cannot reach the API by DNS rebinding.
//!
//! Errors are `{"error": message}`: 400 for bad JSON, an unknown joint or frame, a wrong
//! length or a configuration the library refuses (as `kinetree compute` does); 403 for another
//! `Host`; 404 for an unknown path or any file but the model's meshes (other files of its
//! directory, `..`, absolute paths, symlinks); 405 for a wrong method; 408 for a body that does
//! not arrive within 10 s; 413 for a body over 1 MiB; 431 for a request head over 16 KiB. The
//! server keeps serving after any of them.
//!
//! # Trajectories
//!
//! `--trajectory traj.json` (as `kinetree simulate --out traj.json` writes):
//! `{"trajectory": [{"t": 0.0, "q": {"joint": value, …}}, …]}`, `q` as in the API.

mod api;
mod page;
mod server;

#[cfg(test)]
mod tests;

use anyhow::{Context, Result, bail};
use kinetree::collision::mesh::{candidate_paths, model_search_paths};
use kinetree::collision::{CollisionModel, CollisionOptions};
use kinetree::kinematics::KinematicsData;
use kinetree::model::{Geometry, Model};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Arguments of `kinetree view`.
#[derive(Debug, Default, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// A directory where meshes are looked up after the model file's directory; repeatable.
    #[arg(long = "mesh-path")]
    mesh_paths: Vec<PathBuf>,
    /// An SRDF file whose disabled collision pairs are left out of the collision display.
    #[arg(long)]
    srdf: Option<PathBuf>,
    /// The port to listen on (a free one otherwise).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on. Anything but 127.0.0.1 exposes the model's files to the network.
    #[arg(long, default_value = "127.0.0.1")]
    bind: String,
    /// Do not open a browser; only print the URL.
    #[arg(long)]
    no_open: bool,
    /// The initial configuration `name=value,…` (neutral otherwise).
    #[arg(long)]
    q: Option<String>,
    /// A reachable-workspace point cloud to overlay (`kinetree workspace --out cloud.ply`).
    #[arg(long)]
    workspace: Option<PathBuf>,
    /// A trajectory to play back (`kinetree simulate --out traj.json`).
    #[arg(long)]
    trajectory: Option<PathBuf>,
    /// Write one self-contained HTML file and exit instead of serving.
    #[arg(long)]
    export: Option<PathBuf>,
    /// Relative tolerance of the signed distances shown (as `kinetree collide`'s); 1e-12 to
    /// 1e-3, default 1e-8.
    #[arg(long)]
    distance_tolerance: Option<f64>,
}

/// What the server shares between its workers; read-only after [`State::new`].
#[derive(Debug)]
pub(crate) struct State {
    model: Model,
    /// `/api/model`'s answer (with `initial_q`).
    model_json: Value,
    /// The collision model, or why there is none.
    collision: Result<CollisionModel, String>,
    /// Mesh URL → file: the only files served, and the meshes of the export.
    mesh_files: HashMap<String, PathBuf>,
    /// `/api/trajectory`'s answer.
    trajectory: Value,
    /// The workspace PLY bytes.
    workspace: Option<Vec<u8>>,
    /// The initial configuration.
    initial_q: Vec<f64>,
}

/// The most trajectory samples sent to the page (longer trajectories are thinned evenly).
const MAX_TRAJECTORY_SAMPLES: usize = 5000;

impl State {
    /// Loads the model and everything the page will ask for.
    ///
    /// # Errors
    /// A model, SRDF, trajectory or workspace file that cannot be read or is invalid.
    pub(crate) fn new(args: &Args) -> Result<Self> {
        let model = super::load_model(&args.model, super::root_joint(args.floating))?;
        let search = model_search_paths(&args.model, &args.mesh_paths);
        let mesh_dirs: Vec<PathBuf> = search
            .iter()
            .filter_map(|d| d.canonicalize().ok())
            .collect();
        let mut mesh_files = HashMap::new();
        let mut urls: HashMap<String, String> = HashMap::new();
        for link in model.links() {
            let geometries = link.visuals.iter().map(|v| &v.geometry);
            for g in geometries.chain(link.collisions.iter().map(|c| &c.geometry)) {
                if let Geometry::Mesh { filename, .. } = g {
                    let found = candidate_paths(filename, &search)
                        .into_iter()
                        .find(|p| p.is_file())
                        .and_then(|p| p.canonicalize().ok());
                    if let Some(file) = found
                        && let Some(url) = server::mesh_url(&mesh_dirs, &file)
                    {
                        mesh_files.insert(url.clone(), file);
                        urls.insert(filename.clone(), url);
                    }
                }
            }
        }
        let mut options = CollisionOptions::default()
            .with_model_file(&args.model, &args.mesh_paths)
            .skip_missing_meshes();
        if let Some(srdf) = &args.srdf {
            let text = std::fs::read_to_string(srdf)
                .with_context(|| format!("cannot read {}", srdf.display()))?;
            options.disabled_link_pairs = kinetree::collision::srdf::parse_disabled_pairs(&text)
                .with_context(|| format!("cannot parse {}", srdf.display()))?
                .into_iter()
                .map(|p| (p.link1, p.link2))
                .collect();
        }
        let mut collision = CollisionModel::from_model(&model, &options).map_err(|e| e.to_string());
        if let Some(tol) = args.distance_tolerance {
            match &mut collision {
                Ok(c) => c
                    .set_distance_tolerance(tol)
                    .context("--distance-tolerance")?,
                // Without a collision model the flag is unused, but a bad value is still refused.
                Err(_) if !CollisionModel::DISTANCE_TOLERANCE_RANGE.contains(&tol) => {
                    bail!("--distance-tolerance {tol:e} is outside 1e-12 to 1e-3")
                }
                Err(_) => {}
            }
        }
        let initial_q = super::parse_named(&model, args.q.as_deref(), false)?;
        let mut model_json = api::model_json(&model, &|f| urls.get(f).cloned());
        model_json["initial_q"] = json!(initial_q);
        let trajectory = match &args.trajectory {
            Some(path) => trajectory_json(&model, path)?,
            None => Value::Null,
        };
        let workspace = match &args.workspace {
            Some(path) => Some(
                std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?,
            ),
            None => None,
        };
        Ok(Self {
            model,
            model_json,
            collision,
            mesh_files,
            trajectory,
            workspace,
            initial_q,
        })
    }
}

/// Reads a trajectory file and computes the link poses of each (kept) sample.
fn trajectory_json(model: &Model, path: &Path) -> Result<Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let doc: Value = serde_json::from_str(&text)
        .with_context(|| format!("cannot parse {} as JSON", path.display()))?;
    let samples = doc
        .get("trajectory")
        .or(Some(&doc))
        .and_then(Value::as_array)
        .with_context(|| {
            format!(
                "{}: expected {{\"trajectory\": [{{\"t\": …, \"q\": …}}, …]}}",
                path.display()
            )
        })?;
    if samples.is_empty() {
        bail!("{}: the trajectory is empty", path.display());
    }
    let every = samples.len().div_ceil(MAX_TRAJECTORY_SAMPLES);
    let mut data = KinematicsData::new(model);
    let (mut ts, mut qs, mut links) = (Vec::new(), Vec::new(), Vec::new());
    let mut last_t = f64::NEG_INFINITY;
    for (i, s) in samples.iter().enumerate() {
        let at = || format!("{}: sample {i}", path.display());
        let s = s
            .as_object()
            .with_context(|| format!("{}: not an object", at()))?;
        let t = s
            .get("t")
            .and_then(Value::as_f64)
            .filter(|t| t.is_finite())
            .with_context(|| format!("{}: \"t\" must be a finite number", at()))?;
        if t < last_t {
            bail!("{}: times must not decrease ({t} after {last_t})", at());
        }
        last_t = t;
        let q = api::parse_q(model, s).map_err(|e| anyhow::anyhow!("{}: {}", at(), e.message))?;
        if i % every != 0 && i + 1 != samples.len() {
            continue;
        }
        let poses = api::poses_json(model, &mut data, &q)
            .map_err(|e| anyhow::anyhow!("{}: {}", at(), e.message))?;
        ts.push(t);
        qs.push(q);
        links.push(poses["links"].clone());
    }
    Ok(json!({"t": ts, "q": qs, "links": links}))
}

/// Serves (or exports) until interrupted.
pub(crate) fn run(args: &Args) -> Result<()> {
    let state = State::new(args)?;
    if let Err(reason) = &state.collision {
        eprintln!("note: no collision display: {reason}");
    }
    if let Some(path) = &args.export {
        let html = page::export_html(&state)?;
        std::fs::write(path, html).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
        return Ok(());
    }
    if args.bind != "127.0.0.1" {
        eprintln!(
            "warning: listening on {} makes the model and its mesh files readable by anyone who can reach this address",
            args.bind
        );
    }
    let running = server::start(Arc::new(state), &args.bind, args.port, 4)?;
    let host = if args.bind.contains(':') {
        format!("[{}]", args.bind)
    } else {
        args.bind.clone()
    };
    let url = format!("http://{host}:{}/", running.port);
    println!("kinetree view: serving {url} (Ctrl-C to stop)");
    use std::io::Write;
    let _ = std::io::stdout().flush();
    if !args.no_open {
        open_browser(&url);
    }
    running.join();
    Ok(())
}

/// Opens `url` in the default browser, if one can be found; says so otherwise.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    let spawned = std::process::Command::new(opener)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if spawned.is_err() {
        eprintln!("no browser could be opened ({opener}): open {url} yourself");
    }
}
