//! The queries: any collision (early exit), all colliding pairs with contacts, signed distances
//! per pair, and the same against world obstacles.
//!
//! Every query reads the shape poses of the last
//! [`CollisionData::update_placements`] / [`CollisionData::compute_placements`] and writes its
//! results into the [`CollisionData`]. A broad phase (sort and sweep of the shapes' world
//! bounding boxes along x) finds the pairs whose boxes overlap, so the collision queries run the
//! exact test on those only; the distance queries need every pair and skip it.
//!
//! **Allocation:** none of the queries allocates once the data exists, with these exceptions
//! inside parry: queries involving a triangle mesh ([`MeshMode::TriMesh`](crate::MeshMode))
//! traverse parry's bounding-volume trees, whose stacks move to the heap past 32 entries; and the EPA
//! buffers of [`CollisionData`] grow on the first penetrating convex pairs until they are large
//! enough (they are reused afterwards; parry's own `contact` would allocate a new EPA per call).
//! The distance queries use the crate's own GJK/EPA first (parry's EPA runs to its
//! 100-iteration cap on cylinders), with parry's as the fallback; their buffers also grow on the
//! first calls only.

use crate::data::{CollisionData, Proximity};
use crate::error::CollisionError;
use crate::model::CollisionModel;
use crate::narrow::{Witness, intersects, proximity};
use crate::plan;
use core::ops::ControlFlow;
use kinetree_kinematics::KinematicsData;
use kinetree_kinematics::model::Model;
use parry3d_f64::bounding_volume::Aabb;

/// Whether any candidate pair of shapes, or any shape and world obstacle, overlap. Stops at the
/// first collision found.
///
/// # Errors
/// [`CollisionError::DataMismatch`]; [`CollisionError::Unsupported`] for a pair of shapes parry
/// cannot test.
///
/// # Examples
/// ```
/// use kinetree_collision::{any_collision, CollisionData, CollisionModel, CollisionOptions};
/// use kinetree_collision::kinematics::{configuration, KinematicsData};
/// use kinetree_collision::kinematics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let path = concat!(env!("CARGO_MANIFEST_DIR"),
///                    "/../../tests/data/reference/urdf/panda_collision.urdf");
/// let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
/// let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default())?;
/// let mut kinematics = KinematicsData::new(&model);
/// let mut data = CollisionData::new(&cmodel);
/// let q = configuration::neutral_configuration(&model);
/// data.compute_placements(&model, &cmodel, &mut kinematics, &q)?;
/// // At q = 0 the panda folds its forearm onto the upper arm: links 1 and 3's spheres overlap.
/// assert!(any_collision(&cmodel, &mut data)?);
/// # Ok(())
/// # }
/// ```
pub fn any_collision(
    cmodel: &CollisionModel,
    data: &mut CollisionData,
) -> Result<bool, CollisionError> {
    data.check_model(cmodel)?;
    guarded("any_collision", data, |data| any_overlap(cmodel, data))
}

fn any_overlap(cmodel: &CollisionModel, data: &mut CollisionData) -> Result<bool, CollisionError> {
    let mut result = Ok(false);
    let world = &data.world_from_shape;
    let obstacles = &data.obstacles;
    let scratch = &mut data.scratch;
    let n = cmodel.shapes.len();
    sweep(&mut data.order, &data.aabbs, obstacles, true, |i, j| {
        let (a, b) = (i.min(j), i.max(j));
        let outcome = if b < n {
            if cmodel.pair_index(a, b).is_none() {
                return ControlFlow::Continue(());
            }
            let (sa, sb) = (&cmodel.shapes[a], &cmodel.shapes[b]);
            intersects(sa.posed(&world[a]), sb.posed(&world[b]), scratch)
                .map_err(|_| unsupported(sa.name(), sb.name()))
        } else {
            let (s, o) = (&cmodel.shapes[a], obstacle(obstacles, b - n));
            intersects(s.posed(&world[a]), o.posed(), scratch)
                .map_err(|_| unsupported(s.name(), o.name()))
        };
        match outcome {
            Ok(false) => ControlFlow::Continue(()),
            Ok(true) => {
                result = Ok(true);
                ControlFlow::Break(())
            }
            Err(e) => {
                result = Err(e);
                ControlFlow::Break(())
            }
        }
    });
    result
}

/// Every candidate pair of shapes that overlaps, with its contact: the penetration depth as a
/// negative [`Proximity::distance`] (0 for touching), the deepest points and the normal.
///
/// Stored in [`CollisionData::contacts`] (sorted by pair) and returned. World obstacles are not
/// included (see [`compute_world_collisions`]).
///
/// # Errors
/// [`CollisionError::DataMismatch`]; [`CollisionError::Unsupported`].
pub fn compute_self_collisions<'d>(
    cmodel: &CollisionModel,
    data: &'d mut CollisionData,
) -> Result<&'d [Proximity], CollisionError> {
    data.check_model(cmodel)?;
    guarded("compute_self_collisions", data, |data| {
        self_contacts(cmodel, data)
    })?;
    Ok(&data.contacts)
}

fn self_contacts(cmodel: &CollisionModel, data: &mut CollisionData) -> Result<(), CollisionError> {
    data.contacts.clear();
    let mut result = Ok(());
    let world = &data.world_from_shape;
    let scratch = &mut data.scratch;
    let contacts = &mut data.contacts;
    sweep(&mut data.order, &data.aabbs, &[], false, |i, j| {
        let (a, b) = (i.min(j), i.max(j));
        if cmodel.pair_index(a, b).is_none() {
            return ControlFlow::Continue(());
        }
        let (sa, sb) = (&cmodel.shapes[a], &cmodel.shapes[b]);
        match proximity(sa.posed(&world[a]), sb.posed(&world[b]), 0.0, scratch) {
            Ok(Some(w)) => contacts.push(with_ids(touching(w), a, b)),
            Ok(None) => {}
            Err(_) => {
                result = Err(unsupported(sa.name(), sb.name()));
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    });
    result?;
    data.contacts.sort_unstable_by_key(|c| (c.a, c.b));
    Ok(())
}

/// Every shape–obstacle pair that overlaps, with its contact (as in [`compute_self_collisions`];
/// [`Proximity::b`] is the obstacle's [`ObstacleId`](crate::ObstacleId) index).
///
/// Stored in [`CollisionData::world_contacts`] (sorted by shape, then obstacle) and returned.
///
/// # Errors
/// [`CollisionError::DataMismatch`]; [`CollisionError::Unsupported`].
pub fn compute_world_collisions<'d>(
    cmodel: &CollisionModel,
    data: &'d mut CollisionData,
) -> Result<&'d [Proximity], CollisionError> {
    data.check_model(cmodel)?;
    guarded("compute_world_collisions", data, |data| {
        world_contacts(cmodel, data)
    })?;
    Ok(&data.world_contacts)
}

fn world_contacts(cmodel: &CollisionModel, data: &mut CollisionData) -> Result<(), CollisionError> {
    data.world_contacts.clear();
    let mut result = Ok(());
    let n = cmodel.shapes.len();
    let world = &data.world_from_shape;
    let obstacles = &data.obstacles;
    let scratch = &mut data.scratch;
    let contacts = &mut data.world_contacts;
    sweep(&mut data.order, &data.aabbs, obstacles, true, |i, j| {
        let (a, b) = (i.min(j), i.max(j));
        if b < n {
            return ControlFlow::Continue(());
        }
        let (s, o) = (&cmodel.shapes[a], obstacle(obstacles, b - n));
        match proximity(s.posed(&world[a]), o.posed(), 0.0, scratch) {
            Ok(Some(w)) => contacts.push(with_ids(touching(w), a, b - n)),
            Ok(None) => {}
            Err(_) => {
                result = Err(unsupported(s.name(), o.name()));
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    });
    result?;
    data.world_contacts.sort_unstable_by_key(|c| (c.a, c.b));
    Ok(())
}

/// The signed distance of every candidate pair with its witness points (see [`Proximity`]),
/// and per link pair the minimum over its shape pairs.
///
/// Stored in [`CollisionData::distances`] (pair order) and
/// [`CollisionData`]`::link_pair_distances`; the first is returned.
///
/// # Errors
/// [`CollisionError::DataMismatch`]; [`CollisionError::Unsupported`];
/// [`CollisionError::Overflow`] when a distance is not finite (shapes placed absurdly far).
///
/// # Examples
/// ```
/// use kinetree_collision::{compute_distances, CollisionData, CollisionModel, CollisionOptions};
/// use kinetree_collision::kinematics::{configuration, KinematicsData};
/// use kinetree_collision::kinematics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let path = concat!(env!("CARGO_MANIFEST_DIR"),
///                    "/../../tests/data/reference/urdf/panda_collision.urdf");
/// let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
/// let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default())?;
/// let mut kinematics = KinematicsData::new(&model);
/// let mut data = CollisionData::new(&cmodel);
/// data.compute_placements(&model, &cmodel, &mut kinematics,
///                         &configuration::neutral_configuration(&model))?;
/// let closest = compute_distances(&cmodel, &mut data)?
///     .iter()
///     .min_by(|x, y| x.distance.total_cmp(&y.distance))
///     .copied();
/// if let Some(p) = closest {
///     println!("{} – {}: {:.4} m", cmodel.shapes()[p.a].name(), cmodel.shapes()[p.b].name(), p.distance);
/// }
/// # Ok(())
/// # }
/// ```
pub fn compute_distances<'d>(
    cmodel: &CollisionModel,
    data: &'d mut CollisionData,
) -> Result<&'d [Proximity], CollisionError> {
    data.check_model(cmodel)?;
    guarded("compute_distances", data, |data| {
        pair_distances(cmodel, data)
    })?;
    Ok(&data.distances)
}

fn pair_distances(cmodel: &CollisionModel, data: &mut CollisionData) -> Result<(), CollisionError> {
    data.scratch.polytope.tol = cmodel.distance_tolerance;
    if !distances_by_kind(cmodel, data) {
        // A pair failed (unsupported, or not finite): the loop in pair order names the first.
        for k in 0..cmodel.pairs.len() {
            let w = pair_distance(cmodel, data, k)?;
            data.distances[k] = w;
        }
    }
    for lp in &mut data.link_pair_distances {
        lp.distance = f64::INFINITY;
    }
    for (pair, d) in cmodel.pairs.iter().zip(&data.distances) {
        let lp = &mut data.link_pair_distances[pair.link_pair];
        if d.distance < lp.distance {
            lp.distance = d.distance;
            lp.shape_a = d.a;
            lp.shape_b = d.b;
        }
    }
    Ok(())
}

/// The signed distance of every candidate pair into `data.distances`, kind by kind (see
/// [`crate::plan`]). `false` when a pair failed; its entry is then not written.
fn distances_by_kind(cmodel: &CollisionModel, data: &mut CollisionData) -> bool {
    let plan = &cmodel.plan;
    let mut ok = true;
    let frames = &data.frames;
    let out = &mut data.distances;
    for p in &plan.ball_ball {
        let w = plan::ball_ball(&frames[p.a], &frames[p.b], p.ra, p.rb);
        ok &= finite_witness(&w);
        out[p.k] = with_ids(w, p.a, p.b);
    }
    for p in &plan.ball_cylinder {
        let w = plan::ball_and_cylinder(p, &frames[p.ball], &frames[p.cylinder]);
        ok &= finite_witness(&w);
        out[p.k] = if p.ball_first {
            with_ids(w, p.ball, p.cylinder)
        } else {
            with_ids(w, p.cylinder, p.ball)
        };
    }
    for p in &plan.cylinder_cylinder {
        let fast = plan::cylinders(p, &data.frames[p.a], &data.frames[p.b], &mut data.scratch);
        let w = match fast {
            Some(w) if finite_witness(&w) => with_ids(w, p.a, p.b),
            Some(_) => {
                ok = false;
                continue;
            }
            None => match pair_distance(cmodel, data, p.k) {
                Ok(w) => w,
                Err(_) => {
                    ok = false;
                    continue;
                }
            },
        };
        data.distances[p.k] = w;
    }
    for &k in &plan.general {
        match pair_distance(cmodel, data, k) {
            Ok(w) => data.distances[k] = w,
            Err(_) => ok = false,
        }
    }
    ok
}

/// The signed distance of pair `k` through the general path.
pub(crate) fn pair_distance(
    cmodel: &CollisionModel,
    data: &mut CollisionData,
    k: usize,
) -> Result<Proximity, CollisionError> {
    let pair = &cmodel.pairs[k];
    let (a, b) = (pair.shape_a, pair.shape_b);
    let (sa, sb) = (&cmodel.shapes[a], &cmodel.shapes[b]);
    let (world, frames) = (&data.world_from_shape, &data.frames);
    let w = crate::frames::distance(
        sa.posed(&world[a]),
        &frames[a],
        sb.posed(&world[b]),
        &frames[b],
        &mut data.scratch,
    )
    .map_err(|_| unsupported(sa.name(), sb.name()))?
    // With no distance bound, only a NaN distance gives no witness.
    .filter(finite_witness)
    .ok_or_else(|| overflow(sa.name(), sb.name()))?;
    Ok(with_ids(w, a, b))
}

/// The signed distance between every shape and every world obstacle, with witness points
/// ([`Proximity::b`] is the obstacle index).
///
/// Stored in [`CollisionData::world_distances`] (by shape, then obstacle) and returned.
///
/// # Errors
/// [`CollisionError::DataMismatch`]; [`CollisionError::Unsupported`];
/// [`CollisionError::Overflow`] when a distance is not finite (shapes placed absurdly far).
pub fn compute_world_distances<'d>(
    cmodel: &CollisionModel,
    data: &'d mut CollisionData,
) -> Result<&'d [Proximity], CollisionError> {
    data.check_model(cmodel)?;
    guarded("compute_world_distances", data, |data| {
        world_distances(cmodel, data)
    })?;
    Ok(&data.world_distances)
}

fn world_distances(
    cmodel: &CollisionModel,
    data: &mut CollisionData,
) -> Result<(), CollisionError> {
    data.scratch.polytope.tol = cmodel.distance_tolerance;
    data.world_distances.clear();
    let world = &data.world_from_shape;
    for (a, s) in cmodel.shapes.iter().enumerate() {
        for (k, o) in data.obstacles.iter().enumerate() {
            let Some(o) = o else { continue };
            let w = proximity(
                s.posed(&world[a]),
                o.posed(),
                f64::INFINITY,
                &mut data.scratch,
            )
            .map_err(|_| unsupported(s.name(), o.name()))?
            .filter(finite_witness)
            .ok_or_else(|| overflow(s.name(), o.name()))?;
            data.world_distances.push(with_ids(w, a, k));
        }
    }
    Ok(())
}

/// Runs a query's `body`, turning a panic inside it (a bug in parry, which the queries call
/// into) into [`CollisionError::Panic`] instead of letting it unwind through the caller (and
/// poison the caller's locks). The narrow phase's scratch buffers are reset then, so the data
/// answers the next query as a new one would. Catching costs nothing while nothing panics.
fn guarded<T>(
    query: &'static str,
    data: &mut CollisionData,
    body: impl FnOnce(&mut CollisionData) -> Result<T, CollisionError>,
) -> Result<T, CollisionError> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| body(&mut *data))) {
        Ok(result) => result,
        Err(payload) => {
            data.scratch = crate::narrow::Scratch::default();
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_string());
            Err(CollisionError::Panic { query, message })
        }
    }
}

/// For configuration `q` (length `model.nq()`): forward kinematics, shape placement and
/// [`compute_distances`], then one `(link_a, link_b, distance)` per candidate link pair, the
/// minimum signed distance over their shape pairs, in the order of
/// [`CollisionModel::link_pairs`]. This is the `collision` entry of `kinetree compute` and the
/// quantity the reference regression compares.
///
/// Allocates the returned vector; [`CollisionData`]`::link_pair_distances` is the
/// allocation-free form.
///
/// # Errors
/// As [`CollisionData::compute_placements`] and [`compute_distances`].
pub fn compute_link_pair_distances<'m>(
    model: &'m Model,
    cmodel: &CollisionModel,
    kinematics: &mut KinematicsData,
    data: &mut CollisionData,
    q: &[f64],
) -> Result<Vec<(&'m str, &'m str, f64)>, CollisionError> {
    data.compute_placements(model, cmodel, kinematics, q)?;
    compute_distances(cmodel, data)?;
    Ok(data
        .link_pair_distances
        .iter()
        .map(|d| {
            (
                model.link(d.link_a).name.as_str(),
                model.link(d.link_b).name.as_str(),
                d.distance,
            )
        })
        .collect())
}

/// A contact found by the zero-margin narrow phase: GJK accepts separations within its
/// tolerance (about 1e-10 m) as contact, and such a pair is listed as touching (distance 0),
/// never with a positive distance.
fn touching(w: Witness) -> Witness {
    Witness {
        distance: w.distance.min(0.0),
        ..w
    }
}

fn with_ids(w: Witness, a: usize, b: usize) -> Proximity {
    Proximity {
        a,
        b,
        distance: w.distance,
        point_a: w.point_a,
        point_b: w.point_b,
        normal: w.normal,
    }
}

/// A witness whose distance and points are all finite.
fn finite_witness(w: &Witness) -> bool {
    w.distance.is_finite() && w.point_a.is_finite() && w.point_b.is_finite()
}

fn overflow(a: &str, b: &str) -> CollisionError {
    CollisionError::Overflow {
        shape_a: a.to_string(),
        shape_b: b.to_string(),
    }
}

fn unsupported(a: &str, b: &str) -> CollisionError {
    CollisionError::Unsupported {
        shape_a: a.to_string(),
        shape_b: b.to_string(),
    }
}

fn obstacle(obstacles: &[Option<crate::data::Obstacle>], k: usize) -> &crate::data::Obstacle {
    obstacles[k]
        .as_ref()
        .unwrap_or_else(|| unreachable!("the sweep only visits live obstacles"))
}

/// Sort and sweep along x: calls `f(i, j)` for every pair of entries whose boxes overlap, where
/// entries `0..aabbs.len()` are shapes and `aabbs.len() + k` is obstacle `k` (when
/// `with_obstacles`). Obstacle–obstacle pairs are not reported. Stops when `f` breaks.
fn sweep(
    order: &mut Vec<usize>,
    aabbs: &[Aabb],
    obstacles: &[Option<crate::data::Obstacle>],
    with_obstacles: bool,
    mut f: impl FnMut(usize, usize) -> ControlFlow<()>,
) {
    let n = aabbs.len();
    let aabb = |i: usize| -> &Aabb {
        if i < n {
            &aabbs[i]
        } else {
            &obstacles[i - n]
                .as_ref()
                .unwrap_or_else(|| unreachable!("only live obstacles are sorted"))
                .aabb
        }
    };
    order.clear();
    order.extend(0..n);
    if with_obstacles {
        order.extend(
            obstacles
                .iter()
                .enumerate()
                .filter(|(_, o)| o.is_some())
                .map(|(k, _)| n + k),
        );
    }
    order.sort_unstable_by(|&i, &j| aabb(i).mins.x.total_cmp(&aabb(j).mins.x));
    for (k, &i) in order.iter().enumerate() {
        let bi = aabb(i);
        for &j in &order[k + 1..] {
            let bj = aabb(j);
            if bj.mins.x > bi.maxs.x {
                break;
            }
            if i >= n && j >= n {
                continue;
            }
            if bi.mins.y <= bj.maxs.y
                && bj.mins.y <= bi.maxs.y
                && bi.mins.z <= bj.maxs.z
                && bj.mins.z <= bi.maxs.z
                && f(i, j).is_break()
            {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CollisionOptions;
    use kinetree_kinematics::configuration::neutral_configuration;
    use kinetree_kinematics::model::RootJoint;

    /// A panic inside a query's body is a typed error, and the data answers the next query as
    /// before.
    #[test]
    fn a_panic_in_a_query_is_an_error_and_the_data_stays_usable() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/reference/urdf/panda_collision.urdf"
        );
        let model = Model::from_urdf_file(path, RootJoint::Fixed).unwrap();
        let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
        let mut kinematics = KinematicsData::new(&model);
        let mut data = CollisionData::new(&cmodel);
        let q = neutral_configuration(&model);
        data.compute_placements(&model, &cmodel, &mut kinematics, &q)
            .unwrap();
        let before = compute_distances(&cmodel, &mut data).unwrap().to_vec();
        let failed: Result<(), _> = guarded("test", &mut data, |data| {
            pair_distances(&cmodel, data)?;
            panic!("index out of bounds: the len is 0 but the index is 0")
        });
        match failed {
            Err(CollisionError::Panic { query, message }) => {
                assert_eq!(query, "test");
                assert!(message.starts_with("index out of bounds"), "{message}");
            }
            other => panic!("{other:?}"),
        }
        let after = compute_distances(&cmodel, &mut data).unwrap();
        assert_eq!(after, &before[..]);
        assert!(!any_collision(&cmodel, &mut data).unwrap() || !before.is_empty());
    }
}
