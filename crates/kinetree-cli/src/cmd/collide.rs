//! `kinetree collide <model> --q name=value,… [--obstacles scene.json] [--distance-tolerance
//! tol]`: colliding pairs and the closest pairs of a configuration, against itself and against
//! world obstacles.
//!
//! A scene file holds `{"obstacles": [{"name": "table", "geometry": {"type": "box", "size":
//! [1, 1, 0.1]}, "xyz": [0.5, 0, 0.3], "rpy": [0, 0, 0]}]}` (geometry as in kinetree's JSON
//! model format: box, cylinder, sphere, capsule, mesh), read by
//! [`ObstacleScene`](kinetree::collision::ObstacleScene).

use anyhow::{Context, Result};
use kinetree::collision::{
    CollisionData, CollisionModel, CollisionOptions, ObstacleScene, compute_distances,
    compute_self_collisions, compute_world_collisions, compute_world_distances,
};
use kinetree::kinematics::KinematicsData;
use std::path::PathBuf;

/// Arguments of `kinetree collide`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint named `root_joint`.
    #[arg(long)]
    floating: bool,
    /// Joint positions `name=value,…` (neutral otherwise).
    #[arg(long)]
    q: Option<String>,
    /// A JSON scene of world obstacles.
    #[arg(long)]
    obstacles: Option<PathBuf>,
    /// A directory where meshes are looked up (`package://` and relative names) after the
    /// model file's directory; repeatable.
    #[arg(long = "mesh-path")]
    mesh_paths: Vec<PathBuf>,
    /// Skip meshes that cannot be found or read (listed on stderr).
    #[arg(long)]
    skip_missing_meshes: bool,
    /// How many of the closest pairs to list.
    #[arg(long, default_value_t = 10)]
    closest: usize,
    /// Relative tolerance of the signed distances (GJK/EPA stop when within
    /// `tol · max(|d|, 1 mm)` of the exact value); 1e-12 to 1e-3, default 1e-8 (coal's is 1e-6).
    #[arg(long)]
    distance_tolerance: Option<f64>,
    /// Units of `--q` and of the printed depths and distances: `si` (m, rad) or `mm-deg`.
    #[arg(long, value_enum, default_value_t = super::UnitsArg::Si)]
    units: super::UnitsArg,
}

/// Runs the queries and prints the report.
pub(crate) fn run(args: &Args) -> Result<()> {
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    let q = super::parse_named_in(&model, args.q.as_deref(), false, args.units)?;
    let given = if args.q.is_some() {
        "--q"
    } else {
        "the neutral configuration"
    };
    super::note_outside_limits(&model, &q, given);
    let (scale, unit) = (
        args.units.units().length.per_meter(),
        args.units.units().length.as_str(),
    );
    let mut options = CollisionOptions::default().with_model_file(&args.model, &args.mesh_paths);
    if args.skip_missing_meshes {
        options = options.skip_missing_meshes();
    }
    let mut cmodel = CollisionModel::from_model(&model, &options).with_context(|| {
        format!(
            "cannot build the collision model of {}",
            args.model.display()
        )
    })?;
    if let Some(tol) = args.distance_tolerance {
        cmodel
            .set_distance_tolerance(tol)
            .context("--distance-tolerance")?;
    }
    for skipped in cmodel.skipped_meshes() {
        eprintln!("skipped mesh: {skipped}");
    }
    let mut data = CollisionData::new(&cmodel);
    if let Some(path) = &args.obstacles {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let scene = ObstacleScene::from_json_str(&text)
            .with_context(|| format!("cannot parse {}", path.display()))?;
        for o in &scene.obstacles {
            data.add_obstacle(o.name.clone(), &o.geometry, &o.placement(), &options)
                .with_context(|| format!("in {}", path.display()))?;
        }
    }
    let mut kin = KinematicsData::new(&model);
    data.compute_placements(&model, &cmodel, &mut kin, &q)?;
    let shape_link = |s: usize| cmodel.shapes()[s].name();
    let obstacle_name = |data: &CollisionData, id: usize| -> String {
        data.obstacles()
            .find(|(oid, _)| oid.0 == id)
            .map_or_else(|| format!("#{id}"), |(_, o)| o.name().to_string())
    };

    outln!(
        "{}: {} shapes, {} candidate pairs",
        model.name(),
        cmodel.shapes().len(),
        cmodel.pairs().len()
    )?;
    let contacts = compute_self_collisions(&cmodel, &mut data)?.to_vec();
    outln!("self-collisions: {}", contacts.len())?;
    for c in &contacts {
        outln!(
            "  {:<24} {:<24} depth {:.6} {unit}",
            shape_link(c.a),
            shape_link(c.b),
            -c.distance * scale
        )?;
    }
    let world = compute_world_collisions(&cmodel, &mut data)?.to_vec();
    if args.obstacles.is_some() {
        outln!("world collisions: {}", world.len())?;
        for c in &world {
            outln!(
                "  {:<24} {:<24} depth {:.6} {unit}",
                shape_link(c.a),
                obstacle_name(&data, c.b),
                -c.distance * scale
            )?;
        }
    }
    let mut distances = compute_distances(&cmodel, &mut data)?.to_vec();
    distances.sort_by(|x, y| x.distance.total_cmp(&y.distance));
    outln!("closest self pairs (signed distance, {unit}):")?;
    for d in distances.iter().take(args.closest) {
        outln!(
            "  {:<24} {:<24} {:>10.6}",
            shape_link(d.a),
            shape_link(d.b),
            d.distance * scale
        )?;
    }
    if args.obstacles.is_some() {
        let mut w = compute_world_distances(&cmodel, &mut data)?.to_vec();
        w.sort_by(|x, y| x.distance.total_cmp(&y.distance));
        outln!("closest world pairs (signed distance, {unit}):")?;
        for d in w.iter().take(args.closest) {
            outln!(
                "  {:<24} {:<24} {:>10.6}",
                shape_link(d.a),
                obstacle_name(&data, d.b),
                d.distance * scale
            )?;
        }
    }
    Ok(())
}
