//! `Model` methods of the kinematics layer: poses, Jacobians and their time derivatives, frame
//! velocities and accelerations.

use crate::arrays::{in_block, run, run_blocks};
use crate::errors::Family;
use crate::model::PyModel;
use kinetree::dynamics::DynamicsData;
use kinetree::kinematics::batch::{
    KinematicsBatch, forward_kinematics_matrices_batch, frame_jacobian_rows_batch,
};
use kinetree::kinematics::spatial::{Motion, Se3};
use kinetree::kinematics::{
    FrameId, ReferenceFrame, change_reference, compute_frame_jacobian,
    compute_joint_jacobians_time_variation, forward_kinematics,
    forward_kinematics_with_acceleration, forward_kinematics_with_velocity,
    frame_jacobian_time_variation, frame_velocity, relative_transform, update_frame_placements,
};
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::cell::RefCell;
use std::sync::{Mutex, PoisonError};

thread_local! {
    /// Jacobian columns of the calls on this thread (grown to the largest `nv` seen).
    static COLUMNS: RefCell<Vec<Motion>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with `nv` zeroed Jacobian columns of this thread.
pub(crate) fn with_columns<R>(nv: usize, f: impl FnOnce(&mut [Motion]) -> R) -> R {
    COLUMNS.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() < nv {
            c.resize(nv, Motion::ZERO);
        }
        f(&mut c[..nv])
    })
}

/// Writes `x` as a row-major 4 x 4 homogeneous matrix.
pub(crate) fn write_se3(x: &Se3, out: &mut [f64]) {
    for r in 0..3 {
        let row = x.rotation.row(r);
        out[4 * r] = row.x;
        out[4 * r + 1] = row.y;
        out[4 * r + 2] = row.z;
        out[4 * r + 3] = x.translation[r];
    }
    out[12..16].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
}

/// Writes the placements of `links` (every link when `None`) among the placements of all links
/// `world_from_link`, as consecutive row-major 4 x 4 matrices.
fn write_links(world_from_link: &[Se3], links: Option<&[usize]>, out: &mut [f64]) {
    let rows = out.chunks_exact_mut(16);
    match links {
        None => world_from_link
            .iter()
            .zip(rows)
            .for_each(|(x, o)| write_se3(x, o)),
        Some(links) => links
            .iter()
            .zip(rows)
            .for_each(|(&l, o)| write_se3(&world_from_link[l], o)),
    }
}

/// Writes Jacobian columns as a row-major 6 x nv matrix (rows linear, then angular).
pub(crate) fn write_columns(columns: &[Motion], out: &mut [f64]) {
    let nv = columns.len();
    for (k, c) in columns.iter().enumerate() {
        for r in 0..3 {
            out[r * nv + k] = c.linear[r];
            out[(r + 3) * nv + k] = c.angular[r];
        }
    }
}

/// Writes a twist as 6 numbers, linear then angular.
fn write_motion(m: &Motion, out: &mut [f64]) {
    out[..3].copy_from_slice(&m.linear.to_array());
    out[3..].copy_from_slice(&m.angular.to_array());
}

/// Parses a reference-frame name.
pub(crate) fn reference_frame(name: &str, family: Family) -> PyResult<ReferenceFrame> {
    match name {
        "local_world_aligned" | "LOCAL_WORLD_ALIGNED" => Ok(ReferenceFrame::LocalWorldAligned),
        "local" | "LOCAL" => Ok(ReferenceFrame::Local),
        "world" | "WORLD" => Ok(ReferenceFrame::World),
        other => Err(family.err(format!(
            "reference must be \"local_world_aligned\", \"local\" or \"world\", got {other:?}"
        ))),
    }
}

/// `reference` given as a Python string, ``"local_world_aligned"`` when left out. The usual
/// spellings are interned strings, recognised by identity without reading the text.
fn reference_of(
    reference: Option<&Bound<'_, PyString>>,
    family: Family,
) -> PyResult<ReferenceFrame> {
    let Some(r) = reference else {
        return Ok(ReferenceFrame::LocalWorldAligned);
    };
    let py = r.py();
    if r.is(pyo3::intern!(py, "local_world_aligned")) {
        Ok(ReferenceFrame::LocalWorldAligned)
    } else if r.is(pyo3::intern!(py, "local")) {
        Ok(ReferenceFrame::Local)
    } else if r.is(pyo3::intern!(py, "world")) {
        Ok(ReferenceFrame::World)
    } else {
        reference_frame(&r.to_cow()?, family)
    }
}

/// Links and frames found by name, keyed by the Python string object: a script passes the same
/// string object call after call, so a hit is a pointer comparison instead of a UTF-8 copy and a
/// hash lookup. Holding the string keeps its address from being reused by another.
#[derive(Debug, Default)]
pub(crate) struct FrameCache(Mutex<Vec<(Py<PyString>, FrameId)>>);

/// Names a [`FrameCache`] keeps (the oldest is dropped for a new one).
const FRAME_CACHE: usize = 8;

impl PyModel {
    /// Looks up a link or named frame.
    pub(crate) fn frame(&self, name: &str, family: Family) -> PyResult<FrameId> {
        FrameId::find(&self.model, name).map_err(|e| family.err(e.to_string()))
    }

    /// Looks up a link or named frame given as a Python string, through the model's cache.
    pub(crate) fn frame_of(&self, name: &Bound<'_, PyString>, family: Family) -> PyResult<FrameId> {
        let cache = &self.frame_cache.0;
        let lock = || cache.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(&(_, id)) = lock().iter().find(|(s, _)| s.as_ptr() == name.as_ptr()) {
            return Ok(id);
        }
        let id = self.frame(&name.to_cow()?, family)?;
        let mut cached = lock();
        if cached.len() >= FRAME_CACHE {
            cached.remove(0);
        }
        cached.push((name.clone().unbind(), id));
        Ok(id)
    }
}

#[pymethods]
impl PyModel {
    /// World pose of every link as 4 x 4 homogeneous matrices, in ``link_names`` order (a
    /// composite joint's virtual links left out): shape ``(nlinks, 4, 4)``, or
    /// ``(N, nlinks, 4, 4)`` for ``q`` of shape ``(N, nq)``.
    ///
    /// ``out``, when given, is a C-contiguous, writeable float64 array of that shape: the poses
    /// are written into it and it is returned (no new array is made).
    ///
    /// >>> poses = panda.link_placements(panda.neutral())
    /// >>> poses.shape, poses[1, :3, 3]
    /// ((13, 4, 4), array([0.   , 0.   , 0.333]))
    /// >>> buffer = np.empty((13, 4, 4))
    /// >>> panda.link_placements(panda.neutral(), out=buffer) is buffer
    /// True
    #[pyo3(signature = (q, out = None))]
    fn link_placements<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let q = self.q(q, f)?;
        let nl = self.model.links().len();
        let links = self.user_links.as_deref();
        let nu = links.map_or(nl, <[usize]>::len);
        let one = |d: &mut DynamicsData, x: &[&[f64]], out: &mut [f64]| {
            let k = d.kinematics_mut();
            forward_kinematics(&self.model, k, x[0])?;
            write_links(k.world_from_link(), links, out);
            Ok(())
        };
        run_blocks(
            py,
            self,
            &[&q],
            &[nu, 4, 4],
            out,
            f,
            one,
            |b: &mut KinematicsBatch, _, x, out| {
                forward_kinematics_matrices_batch(&self.model, b, x[0], links, out)
                    .map_err(|e| in_block(e.into()))
            },
        )
    }

    /// World pose of every named frame, in ``frame_names`` order: shape ``(nframes, 4, 4)`` (or
    /// stacked).
    fn frame_placements<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let q = self.q(q, f)?;
        let nf = self.model.frames().len();
        run(py, self, &[&q], &[nf, 4, 4], f, |d, x, out| {
            let k = d.kinematics_mut();
            forward_kinematics(&self.model, k, x[0])?;
            update_frame_placements(&self.model, k)?;
            for (x, o) in k.world_from_frame().iter().zip(out.chunks_exact_mut(16)) {
                write_se3(x, o);
            }
            Ok(())
        })
    }

    /// World pose of one link or named frame: shape ``(4, 4)`` (or ``(N, 4, 4)``).
    ///
    /// >>> float(panda.frame_placement(panda.neutral(), "panda_link1")[2, 3])
    /// 0.333
    fn frame_placement<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        name: &Bound<'py, PyString>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let frame = self.frame_of(name, f)?;
        let q = self.q(q, f)?;
        run(py, self, &[&q], &[4, 4], f, |d, x, out| {
            let k = d.kinematics_mut();
            forward_kinematics(&self.model, k, x[0])?;
            if let FrameId::Frame(_) = frame {
                update_frame_placements(&self.model, k)?;
            }
            write_se3(k.world_from(frame)?, out);
            Ok(())
        })
    }

    /// Pose of frame ``b`` in frame ``a`` (``a_from_b``): shape ``(4, 4)`` (or ``(N, 4, 4)``).
    ///
    /// >>> t = panda.relative_transform(panda.neutral(), "panda_link0", "panda_link1")
    /// >>> float(t[2, 3])
    /// 0.333
    fn relative_transform<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        a: &Bound<'py, PyString>,
        b: &Bound<'py, PyString>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let (fa, fb) = (self.frame_of(a, f)?, self.frame_of(b, f)?);
        let q = self.q(q, f)?;
        run(py, self, &[&q], &[4, 4], f, |d, x, out| {
            let k = d.kinematics_mut();
            forward_kinematics(&self.model, k, x[0])?;
            update_frame_placements(&self.model, k)?;
            write_se3(&relative_transform(k, fa, fb)?, out);
            Ok(())
        })
    }

    /// Jacobian of a link or frame: shape ``(6, nv)`` (or ``(N, 6, nv)``), rows linear then
    /// angular, so that ``J @ v`` is the frame's twist in ``reference``
    /// (``"local_world_aligned"``, ``"local"`` or ``"world"``; ``None``, the default, is
    /// ``"local_world_aligned"``).
    ///
    /// ``out``, when given, is a C-contiguous, writeable float64 array of that shape: the
    /// Jacobian is written into it and it is returned.
    ///
    /// >>> J = panda.frame_jacobian(panda.neutral(), "panda_hand_tcp")
    /// >>> J.shape, float(J[5, 0])
    /// ((6, 9), 1.0)
    /// >>> buffer = np.empty((6, 9))
    /// >>> panda.frame_jacobian(panda.neutral(), "panda_hand_tcp", out=buffer) is buffer
    /// True
    #[pyo3(signature = (q, name, reference = None, out = None))]
    fn frame_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        name: &Bound<'py, PyString>,
        reference: Option<&Bound<'py, PyString>>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let frame = self.frame_of(name, f)?;
        let reference = reference_of(reference, f)?;
        let q = self.q(q, f)?;
        let nv = self.model.nv();
        let one = |d: &mut DynamicsData, x: &[&[f64]], out: &mut [f64]| {
            with_columns(nv, |cols| {
                let k = d.kinematics_mut();
                compute_frame_jacobian(&self.model, k, x[0], frame, reference, cols)?;
                write_columns(cols, out);
                Ok(())
            })
        };
        run_blocks(
            py,
            self,
            &[&q],
            &[6, nv],
            out,
            f,
            one,
            |b: &mut KinematicsBatch, _, x, out| {
                frame_jacobian_rows_batch(&self.model, b, x[0], frame, reference, out)
                    .map_err(|e| in_block(e.into()))
            },
        )
    }

    /// Time derivative of the frame Jacobian at ``(q, v)``: shape ``(6, nv)`` (or stacked), in
    /// ``reference`` as ``frame_jacobian``.
    ///
    /// >>> bool(panda.frame_jacobian_time_variation(panda.neutral(), [0.0] * 9, "panda_hand_tcp").any())
    /// False
    #[pyo3(signature = (q, v, name, reference = None))]
    fn frame_jacobian_time_variation<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        name: &Bound<'py, PyString>,
        reference: Option<&Bound<'py, PyString>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let frame = self.frame_of(name, f)?;
        let reference = reference_of(reference, f)?;
        let (q, v) = (self.q(q, f)?, self.v(v, "v", f)?);
        let nv = self.model.nv();
        run(py, self, &[&q, &v], &[6, nv], f, |d, x, out| {
            with_columns(nv, |cols| {
                let k = d.kinematics_mut();
                compute_joint_jacobians_time_variation(&self.model, k, x[0], x[1])?;
                frame_jacobian_time_variation(&self.model, k, frame, reference, cols)?;
                write_columns(cols, out);
                Ok(())
            })
        })
    }

    /// Twist of a link or frame at ``(q, v)``: shape ``(6,)`` (linear, angular; or ``(N, 6)``)
    /// in ``reference``.
    ///
    /// >>> q, v = panda.neutral(), panda.v_from_dict({"panda_joint1": 2.0})
    /// >>> float(panda.frame_velocity(q, v, "panda_link1")[5])
    /// 2.0
    #[pyo3(signature = (q, v, name, reference = None))]
    fn frame_velocity<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        name: &Bound<'py, PyString>,
        reference: Option<&Bound<'py, PyString>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let frame = self.frame_of(name, f)?;
        let reference = reference_of(reference, f)?;
        let (q, v) = (self.q(q, f)?, self.v(v, "v", f)?);
        run(py, self, &[&q, &v], &[6], f, |d, x, out| {
            let k = d.kinematics_mut();
            forward_kinematics_with_velocity(&self.model, k, x[0], x[1])?;
            write_motion(&frame_velocity(&self.model, k, frame, reference)?, out);
            Ok(())
        })
    }

    /// Spatial acceleration of a link or frame at ``(q, v, a)`` (gravity not included): shape
    /// ``(6,)`` (or ``(N, 6)``) in ``reference``, as Pinocchio's ``getFrameAcceleration``.
    ///
    /// >>> q, a = panda.neutral(), panda.v_from_dict({"panda_joint1": 3.0})
    /// >>> float(panda.frame_acceleration(q, [0.0] * 9, a, "panda_link1")[5])
    /// 3.0
    #[pyo3(signature = (q, v, a, name, reference = None))]
    fn frame_acceleration<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
        name: &Bound<'py, PyString>,
        reference: Option<&Bound<'py, PyString>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Kinematics;
        let frame = self.frame_of(name, f)?;
        let reference = reference_of(reference, f)?;
        let (q, v, a) = (self.q(q, f)?, self.v(v, "v", f)?, self.v(a, "a", f)?);
        run(py, self, &[&q, &v, &a], &[6], f, |d, x, out| {
            let k = d.kinematics_mut();
            forward_kinematics_with_acceleration(&self.model, k, x[0], x[1], x[2])?;
            let (body, body_from_frame) = frame.body(&self.model)?;
            let local = body_from_frame.act_inv_motion(&k.body_acceleration()[body]);
            let world_from_frame = k.world_from_body()[body] * body_from_frame;
            write_motion(&change_reference(&world_from_frame, &local, reference), out);
            Ok(())
        })
    }
}
