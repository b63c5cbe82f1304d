//! `CollisionModel`: self and world collision of a model's collision geometry (parry), one
//! configuration or a stack of them in parallel.

use crate::arrays::{Real, States, to_numpy};
use crate::errors::{Family, py_err};
use crate::model::PyModel;
use kinetree::collision::{
    CollisionData, CollisionModel, CollisionOptions, MeshMode, Proximity, any_collision,
    compute_distances, compute_self_collisions, compute_world_collisions, compute_world_distances,
};
use kinetree::kinematics::KinematicsData;
use kinetree::kinematics::spatial::{DMat3, DVec3, Se3};
use kinetree::model::{Geometry, Model};
use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, RwLock, TryLockError};

const F: Family = Family::Collision;

/// A world obstacle as given from Python, kept to rebuild per-thread data.
#[derive(Clone, Debug)]
struct ObstacleSpec {
    name: String,
    geometry: Geometry,
    pose: Se3,
}

/// The collision geometry of a model: its shapes (one per URDF ``<collision>`` element, named
/// ``<link>_<k>``), the candidate pairs (shapes on different bodies that are not parent and
/// child, minus pairs disabled by an SRDF), and world obstacles added with ``add_obstacle``.
///
/// >>> robot = kinetree.Model.from_urdf("tests/data/reference/urdf/panda_collision.urdf")
/// >>> cm = kinetree.CollisionModel(robot)
/// >>> len(cm.shape_names), cm.npairs
/// (39, 513)
/// >>> cm.any_collision(robot.neutral())  # the folded forearm touches the upper arm
/// True
#[pyclass(module = "kinetree", name = "CollisionModel", frozen)]
#[derive(Debug)]
pub(crate) struct PyCollisionModel {
    model: Arc<Model>,
    /// Replaced (not mutated) by ``set_distance_tolerance``, so running queries keep theirs.
    cmodel: RwLock<Arc<CollisionModel>>,
    options: CollisionOptions,
    obstacles: Mutex<Vec<ObstacleSpec>>,
    scratch: Mutex<(KinematicsData, CollisionData)>,
}

/// Locks `mutex`, recovering it when a panic poisoned it: the collision queries catch parry's
/// panics (`CollisionError::Panic`), and what the locks hold (obstacle specifications, buffers
/// every query rebuilds) stays valid after any other, so one failure must not make every later
/// call raise.
fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| {
        mutex.clear_poison();
        poisoned.into_inner()
    })
}

impl PyCollisionModel {
    /// The current collision model.
    fn cm(&self) -> Arc<CollisionModel> {
        Arc::clone(
            &self
                .cmodel
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        )
    }

    fn new_data(
        &self,
        obstacles: &[ObstacleSpec],
    ) -> Result<(KinematicsData, CollisionData), kinetree::Error> {
        let mut data = CollisionData::new(&self.cm());
        for o in obstacles {
            data.add_obstacle(o.name.clone(), &o.geometry, &o.pose, &self.options)?;
        }
        Ok((KinematicsData::new(&self.model), data))
    }

    fn obstacles(&self) -> PyResult<Vec<ObstacleSpec>> {
        Ok(lock(&self.obstacles).clone())
    }

    /// Runs `f` on one configuration with the shared buffers.
    fn one<R>(
        &self,
        q: &[f64],
        f: impl FnOnce(&CollisionModel, &mut CollisionData) -> Result<R, kinetree::Error>,
    ) -> PyResult<R> {
        let cmodel = self.cm();
        let run = |(k, d): &mut (KinematicsData, CollisionData)| -> Result<R, kinetree::Error> {
            d.compute_placements(&self.model, &cmodel, k, q)?;
            f(&cmodel, d)
        };
        match self.scratch.try_lock() {
            Ok(mut s) => run(&mut s),
            Err(TryLockError::Poisoned(p)) => {
                // A panic left the buffers in an unknown state: start again from fresh ones.
                let mut s = p.into_inner();
                *s = self.new_data(&self.obstacles()?).map_err(py_err)?;
                self.scratch.clear_poison();
                run(&mut s)
            }
            Err(TryLockError::WouldBlock) => {
                let mut fresh = self.new_data(&self.obstacles()?).map_err(py_err)?;
                run(&mut fresh)
            }
        }
        .map_err(py_err)
    }

    fn q(&self, obj: &Bound<'_, PyAny>) -> PyResult<States> {
        crate::arrays::states(obj, "q", self.model.nq(), F)
    }

    fn proximities<'py>(
        &self,
        py: Python<'py>,
        list: &[Proximity],
        world: bool,
    ) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        let obstacles = self.obstacles()?;
        let cmodel = self.cm();
        for p in list {
            let d = PyDict::new(py);
            d.set_item("a", cmodel.shapes()[p.a].name())?;
            let b = if world {
                obstacles
                    .get(p.b)
                    .map_or_else(|| format!("obstacle {}", p.b), |o| o.name.clone())
            } else {
                cmodel.shapes()[p.b].name().to_string()
            };
            d.set_item("b", b)?;
            d.set_item("distance", p.distance)?;
            d.set_item(
                "point_a",
                to_numpy(py, &[3], p.point_a.to_array().to_vec())?,
            )?;
            d.set_item(
                "point_b",
                to_numpy(py, &[3], p.point_b.to_array().to_vec())?,
            )?;
            d.set_item("normal", to_numpy(py, &[3], p.normal.to_array().to_vec())?)?;
            out.append(d)?;
        }
        Ok(out)
    }
}

/// A pose of shape (4, 4).
fn pose(obj: &Bound<'_, PyAny>) -> PyResult<Se3> {
    crate::arrays::real_dtype(obj, "pose", "a float64 array of shape (4, 4)", F)?;
    let array = obj
        .extract::<PyArrayLikeDyn<'_, f64, AllowTypeChange>>()
        .map_err(|e| {
            F.err(format!(
                "pose must be a float64 array of shape (4, 4) ({e})"
            ))
        })?;
    if array.shape() != [4, 4] {
        return Err(F.err(format!(
            "pose must have shape (4, 4), got {}",
            crate::arrays::shape_text(array.shape())
        )));
    }
    let m: Vec<f64> = array.as_array().iter().copied().collect();
    if m.iter().any(|x| !x.is_finite()) {
        return Err(F.err("pose has a NaN or infinite entry: inputs must be finite"));
    }
    let rotation = DMat3::from_cols(
        DVec3::new(m[0], m[4], m[8]),
        DVec3::new(m[1], m[5], m[9]),
        DVec3::new(m[2], m[6], m[10]),
    );
    Se3::from_rotation_translation_checked(rotation, DVec3::new(m[3], m[7], m[11]))
        .ok_or_else(|| F.err("pose: the upper-left 3 x 3 block is not a rotation matrix"))
}

#[pymethods]
impl PyCollisionModel {
    /// The collision model of ``model``. ``mesh_paths``: directories where mesh files are looked
    /// up (``package://pkg/x.stl`` as ``dir/pkg/x.stl`` and ``dir/x.stl``); ``srdf``: an SRDF
    /// file or text whose ``disable_collisions`` pairs are left out; ``convex=True`` uses the
    /// convex hulls of meshes; ``skip_missing_meshes=True`` leaves out meshes that do not load.
    #[new]
    #[pyo3(signature = (model, mesh_paths = Vec::new(), srdf = None, convex = false, skip_missing_meshes = false))]
    fn new(
        model: &PyModel,
        mesh_paths: Vec<PathBuf>,
        srdf: Option<&Bound<'_, PyAny>>,
        convex: bool,
        skip_missing_meshes: bool,
    ) -> PyResult<Self> {
        let mut options = CollisionOptions::default();
        for p in mesh_paths {
            options = options.with_mesh_path(p);
        }
        if convex {
            options = options.with_mesh_mode(MeshMode::ConvexHull);
        }
        if skip_missing_meshes {
            options = options.skip_missing_meshes();
        }
        let m = Arc::clone(&model.model);
        let mut cmodel = CollisionModel::from_model(&m, &options).map_err(py_err)?;
        if let Some(s) = srdf {
            let text: String = s
                .extract()
                .ok()
                .filter(|t: &String| t.trim_start().starts_with('<'))
                .map_or_else(
                    || -> PyResult<String> {
                        let path: PathBuf = s.extract()?;
                        std::fs::read_to_string(&path)
                            .map_err(|e| F.err(format!("cannot read SRDF {}: {e}", path.display())))
                    },
                    Ok,
                )?;
            cmodel
                .disable_pairs_from_srdf_str(&m, &text)
                .map_err(py_err)?;
        }
        let data = CollisionData::new(&cmodel);
        let kin = KinematicsData::new(&m);
        Ok(Self {
            model: m,
            cmodel: RwLock::new(Arc::new(cmodel)),
            options,
            obstacles: Mutex::new(Vec::new()),
            scratch: Mutex::new((kin, data)),
        })
    }

    /// Names of the collision shapes.
    #[getter]
    fn shape_names(&self) -> Vec<String> {
        self.cm()
            .shapes()
            .iter()
            .map(|s| s.name().to_string())
            .collect()
    }

    /// Number of candidate shape pairs.
    #[getter]
    fn npairs(&self) -> usize {
        self.cm().pairs().len()
    }

    /// Names of the world obstacles, in id order.
    #[getter]
    fn obstacle_names(&self) -> PyResult<Vec<String>> {
        Ok(self.obstacles()?.into_iter().map(|o| o.name).collect())
    }

    /// Adds a world obstacle: ``kind`` ``"box"`` (``size`` = 3 side lengths), ``"sphere"``
    /// (``size`` = [radius]), ``"cylinder"`` or ``"capsule"`` (``size`` = [radius, length] along
    /// z), at ``pose`` (4 x 4, world frame; default identity). Returns its index.
    ///
    /// >>> robot = kinetree.Model.from_urdf("tests/data/reference/urdf/panda_collision.urdf")
    /// >>> cm = kinetree.CollisionModel(robot)
    /// >>> wall = np.eye(4); wall[0, 3] = 2.0
    /// >>> cm.add_obstacle("wall", "box", [0.1, 2.0, 2.0], wall)
    /// 0
    /// >>> d = cm.world_distances(robot.neutral())
    /// >>> 1.0 < min(x["distance"] for x in d) < 2.0
    /// True
    #[pyo3(signature = (name, kind, size, pose = None))]
    fn add_obstacle(
        &self,
        name: String,
        kind: &str,
        size: &Bound<'_, PyAny>,
        pose: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let what =
            "a sequence of real sizes (box [x, y, z], sphere [r], cylinder or capsule [r, length])";
        crate::arrays::real_dtype(size, "size", what, F)?;
        let size: Vec<f64> = size
            .extract()
            .map_err(|_| F.err(format!("size must be {what}")))?;
        let geometry = match (kind, size.as_slice()) {
            ("box", &[x, y, z]) => Geometry::Box { size: [x, y, z] },
            ("sphere", &[radius]) => Geometry::Sphere { radius },
            ("cylinder", &[radius, length]) => Geometry::Cylinder { radius, length },
            ("capsule", &[radius, length]) => Geometry::Capsule { radius, length },
            _ => {
                return Err(F.err(format!(
                    "obstacle {name:?}: kind {kind:?} with {} sizes; use \"box\" [x, y, z], \"sphere\" [r], \"cylinder\" or \"capsule\" [r, length]",
                    size.len()
                )));
            }
        };
        let pose = match pose {
            Some(p) => self::pose(p)?,
            None => Se3::IDENTITY,
        };
        let spec = ObstacleSpec {
            name,
            geometry,
            pose,
        };
        let mut scratch = lock(&self.scratch);
        scratch
            .1
            .add_obstacle(spec.name.clone(), &spec.geometry, &spec.pose, &self.options)
            .map_err(py_err)?;
        let mut list = lock(&self.obstacles);
        list.push(spec);
        Ok(list.len() - 1)
    }

    /// The relative tolerance of the distance queries (``distances``, ``world_distances``,
    /// ``link_pair_distances``): 1e-8 unless ``set_distance_tolerance`` changed it.
    #[getter]
    fn distance_tolerance(&self) -> f64 {
        self.cm().distance_tolerance()
    }

    /// Sets the relative tolerance ``tol`` at which the distance queries stop their GJK and EPA
    /// iterations: a reported distance ``d`` is within ``tol * max(|d|, 1e-3)`` m above the
    /// exact one (spheres against primitives and cylinders side by side are exact whatever
    /// ``tol``). The default is 1e-8; coal's default, 1e-6, is faster and less precise. Raises
    /// ``CollisionError`` unless ``tol`` is between 1e-12 and 1e-3 (the tolerance is then
    /// unchanged). The collision queries (``any_collision``, ``collisions``) do not use it.
    ///
    /// >>> robot = kinetree.Model.from_urdf("tests/data/reference/urdf/panda_collision.urdf")
    /// >>> cm = kinetree.CollisionModel(robot)
    /// >>> cm.set_distance_tolerance(1e-6)
    /// >>> cm.distance_tolerance
    /// 1e-06
    fn set_distance_tolerance(&self, tol: Real) -> PyResult<()> {
        let mut cmodel = self
            .cmodel
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut changed = CollisionModel::clone(&cmodel);
        changed.set_distance_tolerance(tol.0).map_err(py_err)?;
        *cmodel = Arc::new(changed);
        Ok(())
    }

    /// Removes every world obstacle.
    fn clear_obstacles(&self) -> PyResult<()> {
        lock(&self.scratch).1.clear_obstacles();
        lock(&self.obstacles).clear();
        Ok(())
    }

    /// Whether any candidate pair, or any shape and obstacle, overlaps: a bool, or a bool array
    /// of shape ``(N,)`` for stacked ``q`` (computed in parallel with the GIL released).
    fn any_collision<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q)?;
        match q.count {
            None => {
                let hit = self.one(&q.values, |cm, d| Ok(any_collision(cm, d)?))?;
                Ok(pyo3::types::PyBool::new(py, hit).to_owned().into_any())
            }
            Some(n) => {
                let obstacles = self.obstacles()?;
                let cmodel = self.cm();
                let mut out = vec![false; n];
                let result = py.detach(|| {
                    out.par_iter_mut().enumerate().try_for_each_init(
                        || self.new_data(&obstacles),
                        |state, (i, hit)| {
                            let (k, d) = state.as_mut().map_err(|e| (i, e.to_string()))?;
                            d.compute_placements(&self.model, &cmodel, k, q.state(i))
                                .and_then(|()| any_collision(&cmodel, d))
                                .map(|h| *hit = h)
                                .map_err(|e| (i, e.to_string()))
                        },
                    )
                });
                if let Err((i, e)) = result {
                    return Err(F.err(format!("state {i}: {e}")));
                }
                Ok(numpy::PyArray1::from_vec(py, out).into_any())
            }
        }
    }

    /// The overlapping pairs (self and world) at ``q``: a list of dicts with ``a``, ``b`` (shape
    /// or obstacle names), ``distance`` (minus the penetration depth), witness points
    /// ``point_a``, ``point_b`` and ``normal`` (world frame).
    fn collisions<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyList>> {
        let q = self.one_q(q)?;
        let (own, world) = self.one(&q, |cm, d| {
            let own = compute_self_collisions(cm, d)?.to_vec();
            let world = compute_world_collisions(cm, d)?.to_vec();
            Ok((own, world))
        })?;
        let list = self.proximities(py, &own, false)?;
        for item in self.proximities(py, &world, true)?.iter() {
            list.append(item)?;
        }
        Ok(list)
    }

    /// Signed distances of every candidate pair at ``q``, with witness points (list of dicts as
    /// ``collisions``).
    fn distances<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyList>> {
        let q = self.one_q(q)?;
        let list = self.one(&q, |cm, d| Ok(compute_distances(cm, d)?.to_vec()))?;
        self.proximities(py, &list, false)
    }

    /// Signed distances of every shape to every world obstacle at ``q`` (list of dicts).
    fn world_distances<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyList>> {
        let q = self.one_q(q)?;
        let list = self.one(&q, |cm, d| Ok(compute_world_distances(cm, d)?.to_vec()))?;
        self.proximities(py, &list, true)
    }

    /// The minimum signed distance of each candidate link pair at ``q``: ``{(link_a, link_b):
    /// distance}``.
    fn link_pair_distances<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let q = self.one_q(q)?;
        let pairs = self.one(&q, |cm, d| {
            compute_distances(cm, d)?;
            Ok(d.compute_link_pair_distances().to_vec())
        })?;
        let out = PyDict::new(py);
        let links = self.model.links();
        for p in pairs {
            out.set_item(
                (links[p.link_a].name.as_str(), links[p.link_b].name.as_str()),
                p.distance,
            )?;
        }
        Ok(out)
    }
}

impl PyCollisionModel {
    fn one_q(&self, q: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        let q = self.q(q)?;
        if q.count.is_some() {
            return Err(F.err("this query takes one configuration of shape (nq,)"));
        }
        Ok(q.values.into_vec())
    }
}

/// Adds the collision classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCollisionModel>()?;
    Ok(())
}
