//! `IkSolver` and `IkReport`: inverse kinematics of one or several frames, one goal or a batch
//! of goals solved in parallel with the GIL released.

use crate::arrays::{Count, Real, states, to_numpy};
use crate::errors::{Family, to_py};
use crate::model::PyModel;
use kinetree::kinematics::ik::{IkParams, IkReport, IkSolver, IkStatus, IkTarget};
use kinetree::kinematics::spatial::{DMat3, DVec3, Se3};
use kinetree::kinematics::{FrameId, KinematicsData};
use kinetree::model::Model;
use numpy::{AllowTypeChange, PyArrayDyn, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::sync::{Arc, Mutex};
use std::time::Duration;

const F: Family = Family::Ik;

/// A goal read from Python: a 4 x 4 pose or a 3-vector position.
#[derive(Clone, Copy, Debug)]
enum Goal {
    Pose(Se3),
    Position(DVec3),
}

/// Goals of shape `(4, 4)` / `(3,)`, or stacked `(N, 4, 4)` / `(N, 3)`.
fn goals(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<Goal>, bool)> {
    let bad = |what: String| {
        F.err(format!(
            "{name} must be a pose of shape (4, 4) or a position of shape (3,) (or stacks of them: (N, 4, 4), (N, 3)); {what}"
        ))
    };
    crate::arrays::real_dtype(
        obj,
        name,
        "a real pose of shape (4, 4) or position of shape (3,)",
        F,
    )?;
    let array = obj
        .extract::<PyArrayLikeDyn<'_, f64, AllowTypeChange>>()
        .map_err(|e| {
            bad(format!(
                "got something that does not convert to float64 ({e})"
            ))
        })?;
    let shape = array.shape().to_vec();
    // A broadcast view of 10⁹ poses is small; its copy is not: refuse it instead of aborting.
    // An overflowing element count asks for usize::MAX, which `reserve` refuses.
    let len = shape.iter().try_fold(1usize, |n, &k| n.checked_mul(k));
    let mut values = crate::arrays::reserve(len.unwrap_or(usize::MAX), name, F)?;
    values.extend(array.as_array().iter().copied());
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        return Err(F.err(format!(
            "{name} has {} at flat index {k}: inputs must be finite",
            values[k]
        )));
    }
    let (stacked, pose) = match shape.as_slice() {
        [3] => (false, false),
        [4, 4] => (false, true),
        [_, 3] => (true, false),
        [_, 4, 4] => (true, true),
        _ => {
            return Err(bad(format!(
                "got shape {}",
                crate::arrays::shape_text(&shape)
            )));
        }
    };
    let width = if pose { 16 } else { 3 };
    let mut out = Vec::new();
    out.try_reserve_exact(values.len() / width).map_err(|_| {
        F.err(format!(
            "{name}: {} goals do not fit in memory",
            values.len() / width
        ))
    })?;
    for (i, m) in values.chunks_exact(width).enumerate() {
        out.push(if pose {
            if m[12..16] != [0.0, 0.0, 0.0, 1.0] {
                return Err(F.err(format!(
                    "{name}[{i}]: the last row of a pose must be [0, 0, 0, 1], got {:?}",
                    &m[12..16]
                )));
            }
            let rotation = DMat3::from_cols(
                DVec3::new(m[0], m[4], m[8]),
                DVec3::new(m[1], m[5], m[9]),
                DVec3::new(m[2], m[6], m[10]),
            );
            Goal::Pose(Se3::new(rotation, DVec3::new(m[3], m[7], m[11])))
        } else {
            Goal::Position(DVec3::new(m[0], m[1], m[2]))
        });
    }
    Ok((out, stacked))
}

/// The six per-axis weights of a target, when given.
fn six(weights: Option<&Bound<'_, PyAny>>) -> PyResult<Option<[f64; 6]>> {
    weights
        .map(|w| crate::arrays::reals::<6>(w, "weights", F))
        .transpose()
}

fn target(frame: FrameId, goal: Goal, weights: Option<[f64; 6]>) -> IkTarget {
    let t = match goal {
        Goal::Pose(x) => IkTarget::new(frame, x),
        Goal::Position(p) => IkTarget::position(frame, p),
    };
    match weights {
        Some(w) => t.with_axis_weights(w),
        None => t,
    }
}

/// How a solve went: ``status`` (``"converged"``, ``"best_effort"`` or ``"failed"``),
/// ``converged``, ``iterations``, ``restarts``, ``position_error`` (m), ``orientation_error``
/// (rad), ``elapsed`` (s) and ``residual`` (the weighted residual of a best-effort result).
#[pyclass(module = "kinetree", name = "IkReport", frozen, get_all)]
#[derive(Clone, Debug)]
pub(crate) struct PyIkReport {
    /// ``"converged"``, ``"best_effort"`` or ``"failed"``.
    status: &'static str,
    /// Whether every target is within the tolerances.
    converged: bool,
    /// Steps taken over every try.
    iterations: usize,
    /// Tries after the first.
    restarts: usize,
    /// Largest position error over the targets (m).
    position_error: f64,
    /// Largest orientation error over the targets (rad).
    orientation_error: f64,
    /// Wall-clock time of the solve (s).
    elapsed: f64,
    /// The weighted residual norm of a best-effort result (``None`` otherwise).
    residual: Option<f64>,
}

impl PyIkReport {
    fn new(r: &IkReport<'_>) -> Self {
        let (status, residual) = match r.status {
            IkStatus::Converged => ("converged", None),
            IkStatus::BestEffort { residual } => ("best_effort", Some(residual)),
            IkStatus::Failed => ("failed", None),
        };
        Self {
            status,
            converged: r.is_converged(),
            iterations: r.iterations,
            restarts: r.restarts,
            position_error: r.position_error,
            orientation_error: r.orientation_error,
            elapsed: r.elapsed.as_secs_f64(),
            residual,
        }
    }
}

#[pymethods]
impl PyIkReport {
    fn __repr__(&self) -> String {
        format!(
            "<kinetree.IkReport {}: position error {:.3e} m, orientation error {:.3e} rad, {} iterations, {} restarts>",
            self.status,
            self.position_error,
            self.orientation_error,
            self.iterations,
            self.restarts
        )
    }
}

/// What a solver needs besides its buffers, to build one per worker thread.
#[derive(Clone, Debug)]
struct Settings {
    params: IkParams,
    moving: Option<Vec<String>>,
    posture: Option<(Vec<f64>, f64)>,
}

impl Settings {
    fn build(&self, model: &Model) -> Result<IkSolver, kinetree::Error> {
        let mut solver = IkSolver::new(model, self.params.clone());
        if let Some(names) = &self.moving {
            solver.set_moving_joints(model, names)?;
        }
        if let Some((q, gain)) = &self.posture {
            solver.set_posture(model, q, *gain)?;
        }
        Ok(solver)
    }
}

/// An inverse-kinematics solver for one model (damped least squares with random restarts; the
/// parameters of the Rust ``IkParams``). ``solve`` places one frame on a pose (4 x 4) or a
/// position (3,); ``solve_targets`` several frames at once; ``solve_batch`` many goals in
/// parallel.
///
/// >>> ik = kinetree.IkSolver(panda, time_budget=None, seed=1)
/// >>> goal = panda.frame_placement(panda.random_configuration(seed=3), "panda_hand_tcp")
/// >>> q, report = ik.solve("panda_hand_tcp", goal)
/// >>> report.converged, bool(np.allclose(panda.frame_placement(q, "panda_hand_tcp"), goal, atol=1e-5))
/// (True, True)
#[pyclass(module = "kinetree", name = "IkSolver", frozen)]
#[derive(Debug)]
pub(crate) struct PyIkSolver {
    model: Arc<Model>,
    settings: Mutex<Settings>,
    /// The solver and data of one-goal calls.
    state: Mutex<Option<(IkSolver, KinematicsData)>>,
}

impl PyIkSolver {
    fn frame(&self, name: &str) -> PyResult<FrameId> {
        FrameId::find(&self.model, name).map_err(|e| F.err(e.to_string()))
    }

    fn q0(&self, q0: Option<&Bound<'_, PyAny>>) -> PyResult<Option<crate::arrays::States>> {
        q0.map(|q| states(q, "q0", self.model.nq(), F)).transpose()
    }

    /// Solves with the shared solver (rebuilt when the settings changed).
    fn solve_one(
        &self,
        py: Python<'_>,
        targets: &[IkTarget],
        q0: &[f64],
    ) -> PyResult<(Vec<f64>, PyIkReport)> {
        let settings = self
            .settings
            .lock()
            .map_err(|_| F.err("solver lock poisoned"))?
            .clone();
        let model = &*self.model;
        let mut state = self
            .state
            .lock()
            .map_err(|_| F.err("solver lock poisoned"))?;
        if state.is_none() {
            let solver = settings.build(model).map_err(|e| to_py(&e, true))?;
            *state = Some((solver, KinematicsData::new(model)));
        }
        let Some((solver, data)) = state.as_mut() else {
            return Err(F.err("no solver"));
        };
        py.detach(|| {
            solver
                .solve_targets(model, data, targets, q0)
                .map(|r| (r.q.to_vec(), PyIkReport::new(&r)))
        })
        .map_err(|e| to_py(&e.into(), true))
    }

    fn reset(&self) {
        if let Ok(mut s) = self.state.lock() {
            *s = None;
        }
    }
}

#[pymethods]
impl PyIkSolver {
    /// A solver for ``model``. Tolerances in metres and radians, ``time_budget`` in seconds
    /// (``None``: no limit, the result then depends only on the inputs and ``seed``); the other
    /// parameters are those of the Rust ``IkParams`` (see its documentation for the defaults).
    #[new]
    #[pyo3(signature = (model, *, position_tolerance = Real(1e-6), orientation_tolerance = Real(1e-5),
        max_iterations = Count::of(10_000), max_iterations_per_try = Count::of(60),
        max_restarts = None, time_budget = Some(Real(0.005)), seed = Count::of(0),
        max_targets = Count::of(4),
        orientation_weight = Real(0.35), damping = Real(0.1)),
        text_signature = "(model, *, position_tolerance=1e-6, orientation_tolerance=1e-5, \
            max_iterations=10000, max_iterations_per_try=60, max_restarts=None, \
            time_budget=0.005, seed=0, max_targets=4, orientation_weight=0.35, damping=0.1)")]
    #[allow(
        clippy::too_many_arguments,
        reason = "a Python signature with keyword defaults"
    )]
    fn new(
        model: &PyModel,
        position_tolerance: Real,
        orientation_tolerance: Real,
        max_iterations: Count,
        max_iterations_per_try: Count,
        max_restarts: Option<Count>,
        time_budget: Option<Real>,
        seed: Count,
        max_targets: Count,
        orientation_weight: Real,
        damping: Real,
    ) -> PyResult<Self> {
        let [max_iterations, max_iterations_per_try, max_targets] = [
            (max_iterations, "max_iterations"),
            (max_iterations_per_try, "max_iterations_per_try"),
            (max_targets, "max_targets"),
        ]
        .map(|(n, name)| n.size(name, F));
        let (max_iterations, max_iterations_per_try, max_targets) =
            (max_iterations?, max_iterations_per_try?, max_targets?);
        if max_targets > kinetree::kinematics::ik::MAX_TARGETS {
            return Err(F.err(format!(
                "max_targets = {max_targets} exceeds the limit of {} targets a solver is sized for",
                kinetree::kinematics::ik::MAX_TARGETS
            )));
        }
        let max_restarts = max_restarts
            .map(|n| n.size("max_restarts", F))
            .transpose()?;
        let seed = seed.get("seed", F)?;
        let [
            position_tolerance,
            orientation_tolerance,
            orientation_weight,
            damping,
        ] = [
            position_tolerance,
            orientation_tolerance,
            orientation_weight,
            damping,
        ]
        .map(|x| x.0);
        for (name, x) in [
            ("position_tolerance", position_tolerance),
            ("orientation_tolerance", orientation_tolerance),
            ("orientation_weight", orientation_weight),
            ("damping", damping),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(F.err(format!("{name} must be finite and not negative, got {x}")));
            }
        }
        // try_from_secs_f64 refuses what a Duration cannot hold (1e308 s) instead of panicking.
        let time_budget = match time_budget.map(|t| t.0) {
            None => None,
            Some(t) => match Duration::try_from_secs_f64(t) {
                Ok(d) => Some(d),
                Err(_) => {
                    return Err(F.err(format!(
                        "time_budget must be None or seconds >= 0 that a duration can hold, got {t:e}"
                    )));
                }
            },
        };
        let params = IkParams {
            position_tolerance,
            orientation_tolerance,
            max_iterations,
            max_iterations_per_try,
            max_restarts: max_restarts.unwrap_or(usize::MAX),
            time_budget,
            seed,
            max_targets,
            orientation_weight,
            damping,
            ..IkParams::default()
        };
        Ok(Self {
            model: Arc::clone(&model.model),
            settings: Mutex::new(Settings {
                params,
                moving: None,
                posture: None,
            }),
            state: Mutex::new(None),
        })
    }

    /// Lets only the named joints move (``None``: every joint on the paths to the targets).
    #[pyo3(signature = (names = None))]
    fn set_moving_joints(&self, names: Option<Vec<String>>) -> PyResult<()> {
        if let Some(n) = &names {
            // Validate now, so that the error comes from this call.
            IkSolver::new(&self.model, IkParams::default())
                .set_moving_joints(&self.model, n)
                .map_err(|e| to_py(&e.into(), true))?;
        }
        self.settings
            .lock()
            .map_err(|_| F.err("solver lock poisoned"))?
            .moving = names;
        self.reset();
        Ok(())
    }

    /// Adds a posture objective: each step also moves a fraction ``gain`` (0..1) towards ``q``
    /// in the null space of the targets (``q=None`` removes it).
    #[pyo3(signature = (q = None, gain = Real(0.1)),
        text_signature = "($self, q=None, gain=0.1)")]
    fn set_posture(&self, q: Option<&Bound<'_, PyAny>>, gain: Real) -> PyResult<()> {
        let gain = gain.0;
        let posture = match q {
            None => None,
            Some(q) => {
                let s = states(q, "q", self.model.nq(), F)?;
                if s.count.is_some() {
                    return Err(F.err("the posture is one configuration of shape (nq,)"));
                }
                IkSolver::new(&self.model, IkParams::default())
                    .set_posture(&self.model, &s.values, gain)
                    .map_err(|e| to_py(&e.into(), true))?;
                Some((s.values.into_vec(), gain))
            }
        };
        self.settings
            .lock()
            .map_err(|_| F.err("solver lock poisoned"))?
            .posture = posture;
        self.reset();
        Ok(())
    }

    /// Places link or frame ``frame`` on ``goal`` (a 4 x 4 world pose, or a position of shape
    /// ``(3,)`` for a position-only target) starting from ``q0`` (default: neutral). ``weights``
    /// are the six per-axis weights (x, y, z, rx, ry, rz in the goal's axes). Returns
    /// ``(q, report)``; not converging is a status in the report, not an error.
    #[pyo3(signature = (frame, goal, q0 = None, weights = None))]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        frame: &str,
        goal: &Bound<'py, PyAny>,
        q0: Option<&Bound<'py, PyAny>>,
        weights: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, PyIkReport)> {
        let weights = six(weights)?;
        let f = self.frame(frame)?;
        let (g, stacked) = goals(goal, "goal")?;
        if stacked {
            return Err(F.err("solve takes one goal; use solve_batch for a stack of goals"));
        }
        let q0 = self.start(q0)?;
        let (q, report) = self.solve_one(py, &[target(f, g[0], weights)], &q0)?;
        Ok((to_numpy(py, &[q.len()], q)?, report))
    }

    /// Several frames at once: ``targets`` is a list of ``(frame, goal)`` or
    /// ``(frame, goal, weights)`` tuples (goals as in ``solve``). Returns ``(q, report)``.
    #[pyo3(signature = (targets, q0 = None))]
    fn solve_targets<'py>(
        &self,
        py: Python<'py>,
        targets: Vec<Bound<'py, PyAny>>,
        q0: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, PyIkReport)> {
        let mut list = Vec::with_capacity(targets.len());
        for (i, t) in targets.iter().enumerate() {
            let (frame, goal, weights): (String, Bound<'py, PyAny>, Option<Bound<'py, PyAny>>) =
                if let Ok((f, g)) = t.extract::<(String, Bound<'py, PyAny>)>() {
                    (f, g, None)
                } else {
                    t.extract().map_err(|_| {
                        F.err(format!(
                            "targets[{i}] must be (frame, goal) or (frame, goal, weights)"
                        ))
                    })?
                };
            let (g, stacked) = goals(&goal, "goal")?;
            if stacked {
                return Err(F.err(format!("targets[{i}] has a stack of goals; give one")));
            }
            list.push(target(self.frame(&frame)?, g[0], six(weights.as_ref())?));
        }
        let q0 = self.start(q0)?;
        let (q, report) = self.solve_one(py, &list, &q0)?;
        Ok((to_numpy(py, &[q.len()], q)?, report))
    }

    /// Solves a stack of goals for one frame in parallel (one solver per thread, the GIL
    /// released): ``goals`` of shape ``(N, 4, 4)`` or ``(N, 3)``, ``q0`` of shape ``(nq,)`` or
    /// ``(N, nq)``. Returns ``(q, info)``: ``q`` of shape ``(N, nq)`` and a dict of arrays
    /// ``converged``, ``position_error``, ``orientation_error``, ``iterations``. Goal ``i`` is
    /// solved exactly as ``solve`` would (same seed), so results equal one-by-one solves when
    /// ``time_budget`` is ``None``.
    #[pyo3(signature = (frame, goals, q0 = None, weights = None))]
    fn solve_batch<'py>(
        &self,
        py: Python<'py>,
        frame: &str,
        goals: &Bound<'py, PyAny>,
        q0: Option<&Bound<'py, PyAny>>,
        weights: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyDict>)> {
        let weights = six(weights)?;
        let f = self.frame(frame)?;
        let (g, _) = self::goals(goals, "goals")?;
        let n = g.len();
        let nq = self.model.nq();
        // One start for every goal, or one per goal (stacked, row i for goal i).
        let (starts, stacked) = match self.q0(q0)? {
            None => (self.start(None)?, false),
            Some(s) => match s.count {
                None => (s.values.into_vec(), false),
                Some(m) if m == n => (s.values.into_vec(), true),
                Some(m) => return Err(F.err(format!("q0 stacks {m} states for {n} goals"))),
            },
        };
        let settings = self
            .settings
            .lock()
            .map_err(|_| F.err("solver lock poisoned"))?
            .clone();
        settings.build(&self.model).map_err(|e| to_py(&e, true))?;
        let model = &*self.model;
        let mut q = crate::arrays::reserve(n.saturating_mul(nq), "the solutions", F)?;
        q.resize(n * nq, 0.0);
        let mut info = Vec::new();
        info.try_reserve_exact(n)
            .map_err(|_| F.err(format!("the reports of {n} goals do not fit in memory")))?;
        info.resize(n, (false, 0.0, 0.0, 0usize));
        let result = py.detach(|| {
            q.par_chunks_mut(nq.max(1))
                .zip(info.par_iter_mut())
                .enumerate()
                .try_for_each_init(
                    || (settings.build(model), KinematicsData::new(model)),
                    |(solver, data), (i, (qi, out))| {
                        let solver = solver.as_mut().map_err(|e| (i, e.to_string()))?;
                        let start = if stacked {
                            &starts[i * nq..(i + 1) * nq]
                        } else {
                            &starts[..]
                        };
                        let r = solver
                            .solve(model, data, &target(f, g[i], weights), start)
                            .map_err(|e| (i, e.to_string()))?;
                        qi.copy_from_slice(r.q);
                        *out = (
                            r.is_converged(),
                            r.position_error,
                            r.orientation_error,
                            r.iterations,
                        );
                        Ok(())
                    },
                )
        });
        if let Err((i, e)) = result {
            return Err(F.err(format!("goal {i}: {e}")));
        }
        let dict = PyDict::new(py);
        dict.set_item("converged", info.iter().map(|x| x.0).collect::<Vec<_>>())?;
        dict.set_item(
            "position_error",
            to_numpy(py, &[n], info.iter().map(|x| x.1).collect())?,
        )?;
        dict.set_item(
            "orientation_error",
            to_numpy(py, &[n], info.iter().map(|x| x.2).collect())?,
        )?;
        dict.set_item("iterations", info.iter().map(|x| x.3).collect::<Vec<_>>())?;
        Ok((to_numpy(py, &[n, nq], q)?, dict))
    }
}

impl PyIkSolver {
    fn start(&self, q0: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<f64>> {
        match self.q0(q0)? {
            None => Ok(kinetree::kinematics::configuration::neutral_configuration(
                &self.model,
            )),
            Some(s) if s.count.is_none() => Ok(s.values.into_vec()),
            Some(_) => Err(F.err("q0 must be one configuration of shape (nq,) here")),
        }
    }
}

/// Adds the IK classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyIkSolver>()?;
    m.add_class::<PyIkReport>()?;
    Ok(())
}
