//! Reachable-workspace sampling: `Model.sample_workspace` returns a `ReachableSet` (arrays of
//! samples) whose `voxelize` gives a `VoxelMap` answering `is_reachable`. Voxel maps pickle and
//! merge, so sampling can be split over processes or machines (see
//! `examples/python/distributed_reachability.py`).

use crate::arrays::{ArrayPair, Count, Real, finite, to_numpy};
use crate::errors::{Family, py_err};
use crate::model::PyModel;
use kinetree::kinematics::spatial::DVec3;
use kinetree::workspace::{
    ReachableParams, ReachableSet, TaskSpace, VoxelMap, VoxelStats, sample_reachable,
};
use numpy::{AllowTypeChange, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::collections::BTreeMap;

const F: Family = Family::Kinematics;

#[pymethods]
impl PyModel {
    /// Samples where link or frame ``frame`` reaches: ``samples`` random configurations within
    /// the joint limits from ``seed``, or with ``grid=K`` the product of ``K`` values per joint on
    /// the frame's path. Runs on every core with the GIL released; the same seed gives the same
    /// samples on any number of threads. ``task="pose"`` also keeps orientations and measures
    /// manipulability on all six Jacobian rows. ``q0`` holds the joints that are not sampled.
    ///
    /// >>> ws = panda.sample_workspace("panda_hand_tcp", samples=2000, seed=0)
    /// >>> ws.positions.shape, ws.manipulability.shape
    /// ((2000, 3), (2000,))
    #[pyo3(signature = (frame, samples = None, seed = Count::of(0), grid = None, task = "position", q0 = None),
        text_signature = "($self, frame, samples=None, seed=0, grid=None, task=\"position\", q0=None)")]
    #[allow(
        clippy::too_many_arguments,
        reason = "a Python signature with keyword defaults"
    )]
    fn sample_workspace(
        &self,
        py: Python<'_>,
        frame: &str,
        samples: Option<Count>,
        seed: Count,
        grid: Option<Count>,
        task: &str,
        q0: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyReachableSet> {
        let id = self.frame(frame, F)?;
        let samples = samples.map(|n| n.size("samples", F)).transpose()?;
        let seed = seed.get("seed", F)?;
        let grid = grid.map(|k| k.size("grid", F)).transpose()?;
        let mut params = match (samples, grid) {
            (Some(n), None) => ReachableParams::random(n, seed),
            (None, Some(k)) => ReachableParams::grid(k),
            (None, None) => ReachableParams::random(100_000, seed),
            (Some(_), Some(_)) => return Err(F.err("give samples or grid, not both")),
        };
        params = params.with_task(match task {
            "position" => TaskSpace::Position,
            "pose" => TaskSpace::Pose,
            other => {
                return Err(F.err(format!(
                    "task must be \"position\" or \"pose\", got {other:?}"
                )));
            }
        });
        if let Some(q0) = q0 {
            let s = self.q(q0, F)?;
            if s.count.is_some() {
                return Err(F.err("q0 must be one configuration of shape (nq,)"));
            }
            params = params.with_q0(s.values.into_vec());
        }
        let model = &*self.model;
        let set = py
            .detach(|| sample_reachable(model, id, &params))
            .map_err(py_err)?;
        Ok(PyReachableSet { set })
    }
}

/// Samples of the positions (and orientations) a frame reaches, with their manipulability.
#[pyclass(module = "kinetree", name = "ReachableSet", frozen)]
#[derive(Debug)]
pub(crate) struct PyReachableSet {
    set: ReachableSet,
}

#[pymethods]
impl PyReachableSet {
    fn __len__(&self) -> usize {
        self.set.len()
    }

    /// The frame sampled.
    #[getter]
    fn frame(&self) -> String {
        self.set.frame_name().to_string()
    }

    /// Names of the joints sampled.
    #[getter]
    fn joints(&self) -> Vec<String> {
        self.set.joints().to_vec()
    }

    /// Frame positions in the world (m), shape ``(n, 3)``.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let p = self.set.positions();
        to_numpy(
            py,
            &[p.len(), 3],
            p.iter().flat_map(|x| x.to_array()).collect(),
        )
    }

    /// Frame orientations as quaternions (x, y, z, w), shape ``(n, 4)``; ``None`` for the
    /// position task.
    #[getter]
    fn orientations<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        self.set
            .orientations()
            .map(|o| {
                to_numpy(
                    py,
                    &[o.len(), 4],
                    o.iter().flat_map(|x| x.to_array()).collect(),
                )
            })
            .transpose()
    }

    /// Yoshikawa manipulability ``sqrt(det(J Jᵀ))`` of each sample, shape ``(n,)``.
    #[getter]
    fn manipulability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let m = self.set.manipulability();
        to_numpy(py, &[m.len()], m.to_vec())
    }

    /// ``(min, max)`` corners of the box holding every sample, each of shape ``(3,)``.
    fn bounds<'py>(&self, py: Python<'py>) -> PyResult<ArrayPair<'py>> {
        let b = self.set.bounds();
        Ok((
            to_numpy(py, &[3], b.min.to_array().to_vec())?,
            to_numpy(py, &[3], b.max.to_array().to_vec())?,
        ))
    }

    /// The largest distance of a sample from ``base`` (m).
    ///
    /// >>> ws = panda.sample_workspace("panda_hand_tcp", samples=20000, seed=0)
    /// >>> 0.8 < ws.max_reach([0, 0, 0.333]) < 1.0
    /// True
    fn max_reach(&self, base: &Bound<'_, PyAny>) -> PyResult<f64> {
        let base = crate::arrays::reals::<3>(base, "base", F)?;
        self.set.max_reach(DVec3::from_array(base)).map_err(py_err)
    }

    /// The voxels of side ``voxel_size`` (m) hit by the samples.
    ///
    /// >>> ws = panda.sample_workspace("panda_hand_tcp", samples=20000, seed=0)
    /// >>> vox = ws.voxelize(0.1)
    /// >>> vox.is_reachable([0.45, 0.05, 0.55]), vox.is_reachable([2.0, 0.0, 0.5])
    /// (True, False)
    fn voxelize(&self, voxel_size: Real) -> PyResult<PyVoxelMap> {
        let map = self.set.voxelize(voxel_size.0).map_err(py_err)?;
        Ok(PyVoxelMap::from_map(&map))
    }
}

/// A voxel map: the voxels of side ``voxel_size`` hit by workspace samples, each with its sample
/// count and the maximum and mean manipulability of its samples. Maps of the same voxel size
/// ``merge`` (so maps sampled by different processes combine), compare equal when they hold the
/// same voxels, and pickle.
#[pyclass(module = "kinetree", name = "VoxelMap", frozen)]
#[derive(Clone, Debug)]
pub(crate) struct PyVoxelMap {
    size: f64,
    /// Sorted by index; the stats of the Rust map (count, max, mean).
    cells: BTreeMap<[i64; 3], VoxelStats>,
}

impl PyVoxelMap {
    fn from_map(map: &VoxelMap) -> Self {
        Self {
            size: map.voxel_size(),
            cells: map.voxels().into_iter().collect(),
        }
    }

    /// The voxel holding `p`, with the rule of the Rust `VoxelMap::index_of`: `floor(p / size)`,
    /// none for a non-finite point or an index beyond 2^52.
    fn lookup(&self, p: DVec3) -> Option<&VoxelStats> {
        let i = (p / self.size).floor();
        if !(i.is_finite() && i.abs().max_element() < (1u64 << 52) as f64) {
            return None;
        }
        self.cells.get(&[i.x as i64, i.y as i64, i.z as i64])
    }
}

/// Points of shape ``(3,)`` or ``(n, 3)``.
fn points(obj: &Bound<'_, PyAny>) -> PyResult<(Vec<DVec3>, bool)> {
    crate::arrays::real_dtype(obj, "point", "a float64 array of shape (3,) or (n, 3)", F)?;
    let array = obj
        .extract::<PyArrayLikeDyn<'_, f64, AllowTypeChange>>()
        .map_err(|e| {
            F.err(format!(
                "point must be a float64 array of shape (3,) or (n, 3) ({e})"
            ))
        })?;
    let shape = array.shape().to_vec();
    let stacked = match shape.as_slice() {
        [3] => false,
        [_, 3] => true,
        _ => {
            return Err(F.err(format!(
                "point must have shape (3,) or (n, 3), got {}",
                crate::arrays::shape_text(&shape)
            )));
        }
    };
    let v: Vec<f64> = array.as_array().iter().copied().collect();
    Ok((
        v.chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect(),
        stacked,
    ))
}

#[pymethods]
impl PyVoxelMap {
    fn __len__(&self) -> usize {
        self.cells.len()
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.size == other.size
            && self.cells.len() == other.cells.len()
            && self.cells.iter().zip(&other.cells).all(|((a, s), (b, t))| {
                a == b && s.count == t.count && s.max_manipulability == t.max_manipulability
            })
    }

    /// The side of a voxel (m).
    #[getter]
    fn voxel_size(&self) -> f64 {
        self.size
    }

    /// The volume of the voxels hit (m³): a lower bound of the reachable volume.
    #[getter]
    fn volume(&self) -> f64 {
        self.cells.len() as f64 * self.size.powi(3)
    }

    /// Whether the voxel holding a point was hit: a bool for a point of shape ``(3,)``, a bool
    /// array for points of shape ``(n, 3)``. Non-finite points are not reachable.
    fn is_reachable<'py>(
        &self,
        py: Python<'py>,
        point: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (pts, stacked) = points(point)?;
        let hits: Vec<bool> = pts.iter().map(|p| self.lookup(*p).is_some()).collect();
        if stacked {
            Ok(numpy::PyArray1::from_vec(py, hits).into_any())
        } else {
            Ok(pyo3::types::PyBool::new(py, hits[0]).to_owned().into_any())
        }
    }

    /// The voxels hit, sorted: ``(indices, counts, max_manipulability, mean_manipulability)``
    /// with ``indices`` of shape ``(n, 3)`` (int64; voxel ``(i, j, k)`` spans
    /// ``[i s, (i + 1) s)`` along x, and so on).
    fn voxels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let n = self.cells.len();
        let idx: Vec<i64> = self.cells.keys().flatten().copied().collect();
        let idx = numpy::PyArray1::from_vec(py, idx).reshape([n, 3])?;
        let counts: Vec<u64> = self.cells.values().map(|s| s.count as u64).collect();
        let max = self.cells.values().map(|s| s.max_manipulability).collect();
        let mean = self.cells.values().map(|s| s.mean_manipulability).collect();
        PyTuple::new(
            py,
            [
                idx.into_any(),
                numpy::PyArray1::from_vec(py, counts).into_any(),
                to_numpy(py, &[n], max)?.into_any(),
                to_numpy(py, &[n], mean)?.into_any(),
            ],
        )
    }

    /// The union of this map and ``other`` (same voxel size): counts add, maxima combine, means
    /// are weighted by the counts.
    ///
    /// >>> a = panda.sample_workspace("panda_hand_tcp", samples=2000, seed=0).voxelize(0.1)
    /// >>> b = panda.sample_workspace("panda_hand_tcp", samples=2000, seed=1).voxelize(0.1)
    /// >>> len(a.merge(b)) >= max(len(a), len(b))
    /// True
    fn merge(&self, other: &Self) -> PyResult<Self> {
        if self.size != other.size {
            return Err(F.err(format!(
                "cannot merge voxel maps of sizes {} and {}",
                self.size, other.size
            )));
        }
        let mut out = self.clone();
        for (k, t) in &other.cells {
            out.cells
                .entry(*k)
                .and_modify(|s| {
                    let n = (s.count + t.count) as f64;
                    s.mean_manipulability = (s.mean_manipulability * s.count as f64
                        + t.mean_manipulability * t.count as f64)
                        / n;
                    s.count += t.count;
                    s.max_manipulability = s.max_manipulability.max(t.max_manipulability);
                })
                .or_insert(*t);
        }
        Ok(out)
    }

    /// Pickling: the voxel size and the voxels.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let this = slf.get();
        let rebuild = py.get_type::<Self>().getattr("_from_voxels")?;
        let cells: Vec<([i64; 3], usize, f64, f64)> = this
            .cells
            .iter()
            .map(|(k, s)| (*k, s.count, s.max_manipulability, s.mean_manipulability))
            .collect();
        let args = PyTuple::new(
            py,
            [
                this.size.into_pyobject(py)?.into_any(),
                cells.into_pyobject(py)?.into_any(),
            ],
        )?;
        Ok((rebuild, args))
    }

    /// Rebuilds a pickled map (internal).
    #[staticmethod]
    fn _from_voxels(size: f64, cells: Vec<([i64; 3], usize, f64, f64)>) -> PyResult<Self> {
        let size = finite(size, "voxel_size", F)?;
        if size <= 0.0 {
            return Err(F.err(format!("voxel_size must be positive, got {size}")));
        }
        Ok(Self {
            size,
            cells: cells
                .into_iter()
                .map(|(k, count, max, mean)| {
                    (
                        k,
                        VoxelStats {
                            count,
                            max_manipulability: max,
                            mean_manipulability: mean,
                        },
                    )
                })
                .collect(),
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<kinetree.VoxelMap {} voxels of {} m, {:.4} m³>",
            self.cells.len(),
            self.size,
            self.volume()
        )
    }
}

/// Adds the workspace classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyReachableSet>()?;
    m.add_class::<PyVoxelMap>()?;
    Ok(())
}
