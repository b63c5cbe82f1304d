//! The `Model` class: loading, sizes, names, limits, configuration-space helpers and pickling.

use crate::arrays::{Count, Real, States, finite, run_with, stack_states, states, to_numpy};
use crate::errors::{Family, py_err};
use crate::kinematics::FrameCache;
use crate::scratch::Pool;
use kinetree::dynamics::batch::{DerivativesBatch, DynamicsBatch};
use kinetree::dynamics::{DerivativesData, DynamicsData};
use kinetree::kinematics::batch::KinematicsBatch;
use kinetree::kinematics::configuration;
use kinetree::model::dh::{DhConvention, DhRow, DhTable};
use kinetree::model::{JointKind, JsonOptions, Model, RootJoint};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use std::path::PathBuf;
use std::sync::Arc;

/// What a model was loaded from, kept so that pickling rebuilds exactly the same model.
#[derive(Clone, Debug)]
pub(crate) enum Source {
    /// URDF text and whether the root floats.
    Urdf(String, bool),
    /// kinetree JSON text (datum files folded in).
    Json(String),
}

/// A kinematic tree (links, joints, frames, inertias, limits), immutable once loaded.
///
/// Load one with `Model.from_urdf`, `Model.from_json` or `Model.from_dh`. Every method takes
/// numpy arrays (or anything convertible to float64) in SI units and returns new arrays; each
/// per-state method also takes a stack of states (`q` of shape `(N, nq)`, and `v`, `a`, `tau`
/// alike) and computes them in parallel with the GIL released. A `Model` pickles and may be
/// shared between threads.
///
/// >>> panda = kinetree.Model.from_urdf("tests/data/robots/panda.urdf")
/// >>> panda.nq, panda.nv, panda.joints[0].name, len(panda.link_names)
/// (9, 9, 'panda_joint1', 13)
#[pyclass(module = "kinetree", name = "Model", frozen)]
#[derive(Debug)]
pub(crate) struct PyModel {
    pub(crate) model: Arc<Model>,
    source: Source,
    /// Dynamics workspaces for reuse by one-state calls and by the workers of stacked calls.
    pub(crate) dynamics_pool: Pool<DynamicsData>,
    /// Workspaces of the derivative algorithms, as `dynamics_pool`.
    pub(crate) derivatives_pool: Pool<DerivativesData>,
    /// Workspaces of the batched kinematics (FK, Jacobians), as `dynamics_pool`.
    pub(crate) kinematics_batch_pool: Pool<KinematicsBatch>,
    /// Workspaces of the batched dynamics (RNEA, ABA, CRBA), as `dynamics_pool`.
    pub(crate) dynamics_batch_pool: Pool<DynamicsBatch>,
    /// Workspaces of the batched derivatives, as `dynamics_pool`.
    pub(crate) derivatives_batch_pool: Pool<DerivativesBatch>,
    /// Links and frames looked up by name (`frame_jacobian`, `frame_placement`).
    pub(crate) frame_cache: FrameCache,
    /// The links users see (indices into the model's links), in depth-first order: all but the
    /// massless virtual links inside composite joints. `None` when there are none of those.
    pub(crate) user_links: Option<Vec<usize>>,
}

impl PyModel {
    pub(crate) fn new(model: Model, source: Source) -> Self {
        let nl = model.links().len();
        let user: Vec<usize> = (0..nl).filter(|&l| !model.is_virtual_link(l)).collect();
        Self {
            user_links: (user.len() < nl).then_some(user),
            model: Arc::new(model),
            source,
            dynamics_pool: Pool::default(),
            derivatives_pool: Pool::default(),
            kinematics_batch_pool: Pool::default(),
            dynamics_batch_pool: Pool::default(),
            derivatives_batch_pool: Pool::default(),
            frame_cache: FrameCache::default(),
        }
    }

    /// The links users see (see [`PyModel::user_links`]), as indices into the model's links.
    pub(crate) fn links(&self) -> Vec<usize> {
        match &self.user_links {
            Some(user) => user.clone(),
            None => (0..self.model.links().len()).collect(),
        }
    }

    /// How many links users see: the length of [`PyModel::links`], without building the list.
    pub(crate) fn nlinks_user(&self) -> usize {
        self.user_links
            .as_ref()
            .map_or(self.model.links().len(), Vec::len)
    }

    /// Reads a configuration argument (`(nq,)` or `(N, nq)`). A large stack is checked finite by
    /// the workers (see [`stack_states`]): give it to [`crate::arrays::map_states`] or
    /// [`crate::parts`], or refuse stacks.
    pub(crate) fn q(&self, obj: &Bound<'_, PyAny>, family: Family) -> PyResult<States> {
        stack_states(obj, "q", self.model.nq(), family)
    }

    /// Reads a velocity-space argument (`(nv,)` or `(N, nv)`) named `name`, checked as
    /// [`PyModel::q`].
    pub(crate) fn v(
        &self,
        obj: &Bound<'_, PyAny>,
        name: &'static str,
        family: Family,
    ) -> PyResult<States> {
        stack_states(obj, name, self.model.nv(), family)
    }
}

/// Text of a file, or the argument itself when it already is the document (starts with `start`).
pub(crate) fn text_or_file(
    arg: &Bound<'_, PyAny>,
    start: char,
) -> PyResult<(String, Option<PathBuf>)> {
    if let Ok(s) = arg.extract::<String>()
        && s.trim_start().starts_with(start)
    {
        return Ok((s, None));
    }
    let path: PathBuf = arg.extract().map_err(|_| {
        Family::Model.err(format!(
            "expected a path (str or os.PathLike) or the document text, got a {}",
            arg.get_type()
                .name()
                .map_or_else(|_| "?".to_string(), |n| n.to_string())
        ))
    })?;
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Family::Model.err(format!("cannot read {}: {e}", path.display())))?;
    Ok((text, Some(path)))
}

pub(crate) fn json_text(model: &Model) -> PyResult<String> {
    model
        .to_json_string(&JsonOptions::default())
        .map_err(py_err)
}

#[pymethods]
impl PyModel {
    /// Loads a URDF file, or URDF text (a string starting with ``<``).
    ///
    /// ``floating=True`` attaches the root link by a 6-DoF joint named ``root_joint``
    /// (q = x, y, z, qx, qy, qz, qw; v = linear, angular in the base frame).
    ///
    /// >>> panda = kinetree.Model.from_urdf("tests/data/robots/panda.urdf")
    /// >>> panda.name, panda.nq
    /// ('panda', 9)
    /// >>> kinetree.Model.from_urdf("tests/data/robots/panda.urdf", floating=True).nq
    /// 16
    #[staticmethod]
    #[pyo3(signature = (path_or_string, floating = false))]
    fn from_urdf(path_or_string: &Bound<'_, PyAny>, floating: bool) -> PyResult<Self> {
        let (text, path) = text_or_file(path_or_string, '<')?;
        let root = if floating {
            RootJoint::Floating
        } else {
            RootJoint::Fixed
        };
        let model = match &path {
            Some(p) => Model::from_urdf_file(p, root),
            None => Model::from_urdf_str(&text, root),
        }
        .map_err(py_err)?;
        Ok(Self::new(model, Source::Urdf(text, floating)))
    }

    /// Loads a kinetree JSON model file, or JSON text (a string starting with ``{``).
    ///
    /// ``floating`` overrides the file's ``root_joint`` when given.
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0], [0.8, 0, 0, 0]])
    /// >>> kinetree.Model.from_json(arm.to_json()).nq
    /// 2
    #[staticmethod]
    #[pyo3(signature = (path_or_string, floating = None))]
    fn from_json(path_or_string: &Bound<'_, PyAny>, floating: Option<bool>) -> PyResult<Self> {
        let (text, path) = text_or_file(path_or_string, '{')?;
        let root = floating.map(|f| {
            if f {
                RootJoint::Floating
            } else {
                RootJoint::Fixed
            }
        });
        let model = match &path {
            Some(p) => Model::from_json_file(p, root),
            None => Model::from_json_str(&text, root),
        }
        .map_err(py_err)?;
        let source = Source::Json(json_text(&model)?);
        Ok(Self::new(model, source))
    }

    /// A serial arm from a Denavit–Hartenberg table: one row ``(a, alpha, d, theta)`` per joint
    /// (metres, radians), standard (distal) DH or, with ``modified=True``, Craig's modified DH.
    ///
    /// ``kinds`` gives each row's joint kind (``"revolute"``, the default, ``"continuous"`` or
    /// ``"prismatic"``). Links are ``base``, ``link1`` …; frames ``dh1`` … mark the DH frames.
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0], [0.8, 0, 0, 0]])
    /// >>> arm.frame_placement([0.0, 0.0], "dh2")[:3, 3]
    /// array([1.8, 0. , 0. ])
    #[staticmethod]
    #[pyo3(signature = (rows, modified = false, kinds = None, name = "dh"))]
    fn from_dh(
        rows: &Bound<'_, PyAny>,
        modified: bool,
        kinds: Option<Vec<String>>,
        name: &str,
    ) -> PyResult<Self> {
        // Refused before the rows are copied (a broadcast view of 10⁸ rows is small).
        let limit = kinetree::model::dh::MAX_DH_ROWS;
        if let Ok(n) = rows.len()
            && n > limit
        {
            return Err(
                Family::Model.err(format!("rows: {n} DH rows, more than the {limit} accepted"))
            );
        }
        let table = states(rows, "rows", 4, Family::Model)?;
        let n = table.count.unwrap_or(1);
        if let Some(k) = &kinds
            && k.len() != n
        {
            return Err(Family::Model.err(format!("kinds has {} entries for {n} DH rows", k.len())));
        }
        let convention = if modified {
            DhConvention::Modified
        } else {
            DhConvention::Standard
        };
        let mut dh = DhTable::new(name, convention);
        for i in 0..n {
            let r = table.state(i);
            let kind = match kinds.as_ref().map(|k| k[i].as_str()) {
                None => JointKind::Revolute,
                Some(s) => JointKind::from_name(s).ok_or_else(|| {
                    Family::Model.err(format!("kinds[{i}] = {s:?} is not a joint kind"))
                })?,
            };
            dh = dh.with_row(DhRow::new(kind, r[0], r[1], r[2], r[3]));
        }
        let model = Model::from_dh(&dh).map_err(py_err)?;
        let source = Source::Json(json_text(&model)?);
        Ok(Self::new(model, source))
    }

    /// The model as URDF text.
    ///
    /// >>> "<robot" in kinetree.Model.from_dh([[1.0, 0, 0, 0]]).to_urdf()
    /// True
    fn to_urdf(&self) -> PyResult<String> {
        self.model.to_urdf_string().map_err(py_err)
    }

    /// The model as kinetree JSON text (SI units).
    ///
    /// >>> import json
    /// >>> json.loads(kinetree.Model.from_dh([[1.0, 0, 0, 0]]).to_json())["name"]
    /// 'dh'
    fn to_json(&self) -> PyResult<String> {
        json_text(&self.model)
    }

    /// Pickling: the model is rebuilt from the text it was loaded from.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let this = slf.get();
        let rebuild = py.get_type::<Self>().getattr("_from_source")?;
        let args = match &this.source {
            Source::Urdf(text, floating) => PyTuple::new(
                py,
                [
                    "urdf".into_pyobject(py)?.into_any(),
                    text.into_pyobject(py)?.into_any(),
                    floating.into_pyobject(py)?.to_owned().into_any(),
                ],
            )?,
            Source::Json(text) => PyTuple::new(
                py,
                [
                    "json".into_pyobject(py)?.into_any(),
                    text.into_pyobject(py)?.into_any(),
                    false.into_pyobject(py)?.to_owned().into_any(),
                ],
            )?,
        };
        Ok((rebuild, args))
    }

    /// Rebuilds a pickled model (internal).
    #[staticmethod]
    fn _from_source(kind: &str, text: String, floating: bool) -> PyResult<Self> {
        match kind {
            "urdf" => {
                let root = if floating {
                    RootJoint::Floating
                } else {
                    RootJoint::Fixed
                };
                let model = Model::from_urdf_str(&text, root).map_err(py_err)?;
                Ok(Self::new(model, Source::Urdf(text, floating)))
            }
            "json" => {
                let model = Model::from_json_str(&text, None).map_err(py_err)?;
                Ok(Self::new(model, Source::Json(text)))
            }
            other => Err(Family::Model.err(format!("unknown model source kind {other:?}"))),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "<kinetree.Model {:?}: nq={}, nv={}, {} links>",
            self.model.name(),
            self.model.nq(),
            self.model.nv(),
            self.nlinks_user()
        )
    }

    /// The model's name.
    #[getter]
    fn name(&self) -> String {
        self.model.name().to_string()
    }

    /// Number of configuration coordinates (length of ``q``).
    #[getter]
    fn nq(&self) -> usize {
        self.model.nq()
    }

    /// Number of velocity coordinates (length of ``v``, ``a``, ``tau``).
    #[getter]
    fn nv(&self) -> usize {
        self.model.nv()
    }

    /// Number of links (the first axis of ``link_placements``; a composite joint's virtual
    /// links are not counted).
    #[getter]
    fn nlinks(&self) -> usize {
        self.nlinks_user()
    }

    /// ``"fixed"`` or ``"floating"``: how the root link is attached to the world.
    #[getter]
    fn root_joint(&self) -> &'static str {
        match self.model.root_joint() {
            RootJoint::Fixed => "fixed",
            RootJoint::Floating => "floating",
        }
    }

    /// The moving joints in ``q`` order, each with ``name``, ``kind``, ``idx_q``, ``nq``,
    /// ``idx_v``, ``nv``, ``parent_link``, ``child_link``; a composite joint is one entry of
    /// kind ``"composite"`` covering its state variables.
    ///
    /// >>> [(j.name, j.idx_q, j.nq) for j in panda.joints][-2:]
    /// [('panda_finger_joint1', 7, 1), ('panda_finger_joint2', 8, 1)]
    #[getter]
    fn joints(&self) -> Vec<PyJoint> {
        let m = &self.model;
        m.moving_user_joints()
            .map(|u| {
                let pieces = m.user_joints()[u].joints.clone();
                let (first, last) = (m.joint(pieces.start), m.joint(pieces.end - 1));
                let (rq, rv) = (m.user_joint_q_range(u), m.user_joint_v_range(u));
                PyJoint {
                    name: m.user_joints()[u].name.clone(),
                    kind: m.user_joint_type(u).to_string(),
                    idx_q: rq.start,
                    nq: rq.len(),
                    idx_v: rv.start,
                    nv: rv.len(),
                    parent_link: first
                        .parent_link
                        .map(|l| m.link(l).name.clone())
                        .unwrap_or_default(),
                    child_link: m.link(last.child_link).name.clone(),
                }
            })
            .collect()
    }

    /// Names of the moving joints, in ``q`` order.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        let m = &self.model;
        m.moving_user_joints()
            .map(|u| m.user_joints()[u].name.clone())
            .collect()
    }

    /// Names of the links, in the order of ``link_placements``: the model's links, without the
    /// massless virtual links kinetree adds inside a composite joint.
    ///
    /// >>> panda.link_names[:2]
    /// ['panda_link0', 'panda_link1']
    #[getter]
    fn link_names(&self) -> Vec<String> {
        let links = self.model.links();
        self.links()
            .into_iter()
            .map(|l| links[l].name.clone())
            .collect()
    }

    /// Names of the named frames (besides links), in the order of ``frame_placements``.
    #[getter]
    fn frame_names(&self) -> Vec<String> {
        self.model.frames().iter().map(|f| f.name.clone()).collect()
    }

    /// Lower position limits, shape ``(nq,)``: ``-inf`` where unlimited, ``-1`` on quaternions.
    #[getter]
    fn lower_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(py, &[self.model.nq()], self.position_limits(false))
    }

    /// Upper position limits, shape ``(nq,)``: ``inf`` where unlimited, ``1`` on quaternions.
    ///
    /// >>> float(panda.upper_limits[0])
    /// 2.8973
    #[getter]
    fn upper_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(py, &[self.model.nq()], self.position_limits(true))
    }

    /// Speed limits per velocity coordinate, shape ``(nv,)`` (``inf`` when unknown).
    #[getter]
    fn velocity_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(py, &[self.model.nv()], self.dof_limits(|l| l.velocity))
    }

    /// Effort limits per velocity coordinate, shape ``(nv,)`` (``inf`` when unknown).
    #[getter]
    fn effort_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(py, &[self.model.nv()], self.dof_limits(|l| l.effort))
    }

    /// Gravity in the world frame (m/s²), shape ``(3,)``.
    #[getter]
    fn gravity_vector<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(py, &[3], self.model.gravity().to_array().to_vec())
    }

    /// Total mass of all links (kg).
    #[getter]
    fn total_mass(&self) -> f64 {
        self.model.total_mass()
    }

    /// The neutral configuration, shape ``(nq,)`` (zeros, identity quaternions).
    ///
    /// >>> kinetree.Model.from_dh([[1.0, 0, 0, 0]]).neutral()
    /// array([0.])
    fn neutral<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        to_numpy(
            py,
            &[self.model.nq()],
            configuration::neutral_configuration(&self.model),
        )
    }

    /// Random configurations uniform within the joint limits: shape ``(nq,)``, or ``(n, nq)``
    /// when ``n`` is given. The same ``seed`` gives the same configurations.
    ///
    /// >>> q = panda.random_configuration(1000, seed=1)
    /// >>> q.shape, bool((q >= panda.lower_limits).all() and (q <= panda.upper_limits).all())
    /// ((1000, 9), True)
    #[pyo3(signature = (n = None, seed = None))]
    fn random_configuration<'py>(
        &self,
        py: Python<'py>,
        n: Option<Count>,
        seed: Option<Count>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let nq = self.model.nq();
        let n = n.map(|n| n.size("n", Family::Kinematics)).transpose()?;
        let seed = seed
            .map(|s| s.get("seed", Family::Kinematics))
            .transpose()?;
        let mut rng = match seed {
            Some(s) => SmallRng::seed_from_u64(s),
            None => SmallRng::seed_from_u64(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos() as u64),
            ),
        };
        let count = n.unwrap_or(1);
        // Refuse a size that cannot be allocated (n = 10**15) instead of aborting the process.
        let mut out = Vec::new();
        count
            .checked_mul(nq)
            .filter(|&len| out.try_reserve_exact(len).is_ok())
            .ok_or_else(|| {
                Family::Kinematics.err(format!(
                    "n = {count} configurations of {nq} coordinates do not fit in memory"
                ))
            })?;
        out.resize(count * nq, 0.0);
        for q in out.chunks_mut(nq.max(1)).take(count) {
            configuration::random_configuration(&self.model, &mut rng, &mut q[..nq])
                .map_err(py_err)?;
        }
        match n {
            None => to_numpy(py, &[nq], out),
            Some(n) => to_numpy(py, &[n, nq], out),
        }
    }

    /// ``q ⊕ v``: the configuration reached from ``q`` moving with velocity ``v`` for unit time.
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0]])
    /// >>> arm.integrate([0.5], [0.25])
    /// array([0.75])
    fn integrate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let (q, v) = (self.q(q, f)?, self.v(v, "v", f)?);
        run_with(py, self, &[&q, &v], &[self.model.nq()], f, |(), x, out| {
            Ok(configuration::integrate(&self.model, x[0], x[1], out)?)
        })
    }

    /// The velocity ``v`` with ``q0 ⊕ v = q1`` (continuous joints take the short way round).
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0]])
    /// >>> arm.difference([0.5], [0.75])
    /// array([0.25])
    fn difference<'py>(
        &self,
        py: Python<'py>,
        q0: &Bound<'py, PyAny>,
        q1: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let q0 = states(q0, "q0", self.model.nq(), f)?;
        let q1 = states(q1, "q1", self.model.nq(), f)?;
        run_with(
            py,
            self,
            &[&q0, &q1],
            &[self.model.nv()],
            f,
            |(), x, out| Ok(configuration::difference(&self.model, x[0], x[1], out)?),
        )
    }

    /// The configuration a fraction ``t`` of the way from ``q0`` to ``q1`` on the manifold.
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0]])
    /// >>> arm.interpolate([0.0], [1.0], 0.25)
    /// array([0.25])
    fn interpolate<'py>(
        &self,
        py: Python<'py>,
        q0: &Bound<'py, PyAny>,
        q1: &Bound<'py, PyAny>,
        t: Real,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let t = finite(t.0, "t", f)?;
        let q0 = states(q0, "q0", self.model.nq(), f)?;
        let q1 = states(q1, "q1", self.model.nq(), f)?;
        run_with(
            py,
            self,
            &[&q0, &q1],
            &[self.model.nq()],
            f,
            |(), x, out| Ok(configuration::interpolate(&self.model, x[0], x[1], t, out)?),
        )
    }

    /// ``q`` with the quaternions of spherical and floating joints normalized.
    ///
    /// >>> solo = kinetree.Model.from_urdf("tests/data/robots/panda.urdf", floating=True)
    /// >>> q = solo.neutral(); q[3:7] = [0, 0, 2, 0]
    /// >>> solo.normalize(q)[3:7]
    /// array([0., 0., 1., 0.])
    fn normalize<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let q = self.q(q, f)?;
        run_with(py, self, &[&q], &[self.model.nq()], f, |(), x, out| {
            out.copy_from_slice(x[0]);
            Ok(configuration::normalize(&self.model, out)?)
        })
    }

    /// A configuration from ``{joint name: value}`` (a number, or a sequence for multi-DoF
    /// joints); joints not named keep their value in ``base`` (default: neutral).
    ///
    /// >>> q = panda.q_from_dict({"panda_joint2": 0.5})
    /// >>> float(q[1]), panda.dict_from_q(q)["panda_joint2"]
    /// (0.5, 0.5)
    #[pyo3(signature = (values, base = None))]
    fn q_from_dict<'py>(
        &self,
        py: Python<'py>,
        values: &Bound<'py, PyDict>,
        base: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let mut q = match base {
            Some(b) => {
                let s = self.q(b, Family::Kinematics)?;
                if s.count.is_some() {
                    return Err(Family::Kinematics.err("base must be one state of shape (nq,)"));
                }
                s.values.into_vec()
            }
            None => configuration::neutral_configuration(&self.model),
        };
        for (k, v) in values.iter() {
            let name: String = k.extract()?;
            let vals = joint_values(&v, &name)?;
            configuration::set_joint_q(&self.model, &mut q, &name, &vals).map_err(py_err)?;
        }
        to_numpy(py, &[self.model.nq()], q)
    }

    /// A velocity-space vector (``v``, ``a`` or ``tau``) from ``{joint name: value}``; joints
    /// not named are zero.
    ///
    /// >>> panda.v_from_dict({"panda_joint1": 1.0})[:2]
    /// array([1., 0.])
    fn v_from_dict<'py>(
        &self,
        py: Python<'py>,
        values: &Bound<'py, PyDict>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let mut v = vec![0.0; self.model.nv()];
        for (k, val) in values.iter() {
            let name: String = k.extract()?;
            let vals = joint_values(&val, &name)?;
            configuration::set_joint_v(&self.model, &mut v, &name, &vals).map_err(py_err)?;
        }
        to_numpy(py, &[self.model.nv()], v)
    }

    /// ``{joint name: value}`` of a configuration (floats for 1-DoF joints, arrays otherwise).
    fn dict_from_q<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let q = self.q(q, Family::Kinematics)?;
        if q.count.is_some() {
            return Err(Family::Kinematics.err("dict_from_q takes one state of shape (nq,)"));
        }
        self.by_joint(py, &q.values, false)
    }

    /// ``{joint name: value}`` of a velocity-space vector (``v``, ``a``, ``tau``).
    fn dict_from_v<'py>(
        &self,
        py: Python<'py>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let v = self.v(v, "v", Family::Kinematics)?;
        if v.count.is_some() {
            return Err(Family::Kinematics.err("dict_from_v takes one state of shape (nv,)"));
        }
        self.by_joint(py, &v.values, true)
    }
}

impl PyModel {
    fn position_limits(&self, upper: bool) -> Vec<f64> {
        let m = &self.model;
        let mut out = vec![0.0; m.nq()];
        let inf = if upper {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        };
        let unit = if upper { 1.0 } else { -1.0 };
        for j in m.moving_joints() {
            let joint = m.joint(j);
            let lim = if upper {
                joint.limits.upper
            } else {
                joint.limits.lower
            };
            let r = m.joint_q_range(j);
            let block = &mut out[r];
            match joint.kind {
                JointKind::Revolute | JointKind::Prismatic => block[0] = lim,
                JointKind::Continuous => block[0] = inf,
                JointKind::Cylindrical => {
                    block[0] = lim;
                    block[1] = inf;
                }
                JointKind::Spherical => block.fill(unit),
                JointKind::Floating => {
                    block[..3].fill(inf);
                    block[3..].fill(unit);
                }
                JointKind::Planar | JointKind::Fixed => block.fill(inf),
            }
        }
        out
    }

    fn dof_limits(&self, pick: impl Fn(&kinetree::model::JointLimits) -> f64) -> Vec<f64> {
        let m = &self.model;
        let mut out = vec![f64::INFINITY; m.nv()];
        for j in m.moving_joints() {
            out[m.joint_v_range(j)].fill(pick(&m.joint(j).limits));
        }
        out
    }

    fn by_joint<'py>(
        &self,
        py: Python<'py>,
        values: &[f64],
        velocity: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let m = &self.model;
        let dict = PyDict::new(py);
        for j in m.moving_user_joints() {
            let r = if velocity {
                m.user_joint_v_range(j)
            } else {
                m.user_joint_q_range(j)
            };
            let name = &m.user_joints()[j].name;
            if r.len() == 1 {
                dict.set_item(name, values[r.start])?;
            } else {
                dict.set_item(name, to_numpy(py, &[r.len()], values[r].to_vec())?)?;
            }
        }
        Ok(dict)
    }
}

/// The numbers given for joint `name` in a dict: a number or a sequence of numbers.
fn joint_values(v: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    crate::arrays::real_dtype(
        v,
        &format!("value of joint {name:?}"),
        "a real number or a sequence of real numbers",
        Family::Kinematics,
    )?;
    if let Ok(x) = v.extract::<f64>() {
        return Ok(vec![x]);
    }
    v.extract::<Vec<f64>>().map_err(|_| {
        Family::Kinematics.err(format!(
            "value of joint {name:?} must be a number or a sequence of numbers"
        ))
    })
}

/// One moving joint of a model: its name, kind and blocks in ``q`` and ``v``.
#[pyclass(module = "kinetree", name = "Joint", frozen, get_all)]
#[derive(Clone, Debug)]
pub(crate) struct PyJoint {
    /// Joint name.
    name: String,
    /// ``"revolute"``, ``"continuous"``, ``"prismatic"``, ``"cylindrical"``, ``"spherical"``,
    /// ``"planar"`` or ``"floating"``.
    kind: String,
    /// First index of the joint's block in ``q``.
    idx_q: usize,
    /// Length of the joint's block in ``q``.
    nq: usize,
    /// First index of the joint's block in ``v``.
    idx_v: usize,
    /// Length of the joint's block in ``v``.
    nv: usize,
    /// Name of the parent link (``""`` for the floating root joint).
    parent_link: String,
    /// Name of the child link.
    child_link: String,
}

#[pymethods]
impl PyJoint {
    fn __repr__(&self) -> String {
        format!(
            "<kinetree.Joint {:?} {}: q[{}:{}], v[{}:{}]>",
            self.name,
            self.kind,
            self.idx_q,
            self.idx_q + self.nq,
            self.idx_v,
            self.idx_v + self.nv
        )
    }
}
