//! `Model` loaders for MJCF, SDFormat and any file by its content, and the conversions between
//! MuJoCo's `qpos`/`qvel`/`qacc`/`qfrc` and kinetree's `q`/`v`/`a`/`tau`.

use crate::arrays::{run_with, states};
use crate::errors::{Family, py_err};
use crate::model::{PyModel, Source, json_text, text_or_file};
use kinetree::model::{Model, RootJoint};
use pyo3::prelude::*;
use std::path::PathBuf;

#[pymethods]
impl PyModel {
    /// Loads an MJCF (MuJoCo XML) file, or MJCF text (a string starting with ``<``): bodies
    /// keep their MuJoCo names, joints their names, and ``q`` is MuJoCo's ``qpos`` up to the
    /// quaternion order (see ``q_from_mujoco``). ``<include>`` and mesh folders are resolved
    /// relative to the file (or to the current directory for text).
    ///
    /// >>> hopper = kinetree.Model.from_mjcf("tests/data/reference/mjcf/models/gym_hopper/hopper.xml")
    /// >>> hopper.name, hopper.nq, [j.name for j in hopper.joints][:3]
    /// ('hopper', 6, ['rootx', 'rootz', 'rooty'])
    #[staticmethod]
    fn from_mjcf(path_or_string: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (text, path) = text_or_file(path_or_string, '<')?;
        let model = match &path {
            Some(p) => Model::from_mjcf_file(p),
            None => Model::from_mjcf_str(&text),
        }
        .map_err(py_err)?;
        let source = Source::Json(json_text(&model)?);
        Ok(Self::new(model, source))
    }

    /// Loads an SDFormat file (``<sdf>``, versions 1.4–1.11), or SDFormat text (a string
    /// starting with ``<``): links and joints keep their names; a tree not attached to the world
    /// floats on a joint named after its root link, at the pose the file gives it.
    ///
    /// >>> acrobot = kinetree.Model.from_sdf(
    /// ...     "tests/data/reference/sdf/drake/models/examples/acrobot/Acrobot.sdf")
    /// >>> acrobot.nq, [j.name for j in acrobot.joints if j.nv]
    /// (2, ['shoulder', 'elbow'])
    #[staticmethod]
    fn from_sdf(path_or_string: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (text, path) = text_or_file(path_or_string, '<')?;
        let model = match &path {
            Some(p) => Model::from_sdf_file(p),
            None => Model::from_sdf_str(&text),
        }
        .map_err(py_err)?;
        let source = Source::Json(json_text(&model)?);
        Ok(Self::new(model, source))
    }

    /// Loads a model file of any format kinetree reads, told by its extension and content:
    /// URDF (``<robot>``), MJCF (``<mujoco>``), SDFormat (``<sdf>``), kinetree JSON, yapCAD and
    /// DH JSON.
    ///
    /// ``floating`` attaches a URDF's root by a 6-DoF joint, or overrides a JSON file's
    /// ``root_joint``; an MJCF file floats its bodies by its own free joints.
    ///
    /// >>> kinetree.Model.load("tests/data/robots/panda.urdf").nq
    /// 9
    /// >>> kinetree.Model.load("tests/data/reference/mjcf/models/gym_ant/ant.xml").nq
    /// 15
    #[staticmethod]
    #[pyo3(signature = (path, floating = None))]
    fn load(path: PathBuf, floating: Option<bool>) -> PyResult<Self> {
        let root = floating.map(|f| {
            if f {
                RootJoint::Floating
            } else {
                RootJoint::Fixed
            }
        });
        let model = Model::from_file(&path, root).map_err(py_err)?;
        let is_urdf = std::fs::read_to_string(&path)
            .ok()
            .filter(|t| t.contains("<robot"))
            .filter(|_| path.extension().is_none_or(|e| e != "json"));
        let source = match is_urdf {
            Some(text) if model.root_joint() == root.unwrap_or_default() => {
                Source::Urdf(text, floating == Some(true))
            }
            _ => Source::Json(json_text(&model)?),
        };
        Ok(Self::new(model, source))
    }

    /// MuJoCo's ``qpos`` as kinetree's ``q``: quaternions of free and ball joints go from
    /// ``[w, x, y, z]`` to ``[x, y, z, w]``. One state ``(nq,)`` or a stack ``(N, nq)``.
    ///
    /// >>> ant = kinetree.Model.load("tests/data/reference/mjcf/models/gym_ant/ant.xml")
    /// >>> ant.q_from_mujoco([0, 0, 0.75, 1, 0, 0, 0] + [0] * 8)[:7]
    /// array([0.  , 0.  , 0.75, 0.  , 0.  , 0.  , 1.  ])
    fn q_from_mujoco<'py>(
        &self,
        py: Python<'py>,
        qpos: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let qpos = states(qpos, "qpos", self.model.nq(), f)?;
        run_with(py, self, &[&qpos], &[self.model.nq()], f, |(), x, out| {
            out.copy_from_slice(&self.model.q_from_mujoco(x[0])?);
            Ok(())
        })
    }

    /// kinetree's ``q`` as MuJoCo's ``qpos`` (the inverse of ``q_from_mujoco``).
    fn q_to_mujoco<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let q = self.q(q, f)?;
        run_with(py, self, &[&q], &[self.model.nq()], f, |(), x, out| {
            out.copy_from_slice(&self.model.q_to_mujoco(x[0])?);
            Ok(())
        })
    }

    /// MuJoCo's ``qvel`` at ``qpos`` as kinetree's ``v``: a free joint's linear velocity goes
    /// from the world frame to the body frame.
    fn v_from_mujoco<'py>(
        &self,
        py: Python<'py>,
        qpos: &Bound<'py, PyAny>,
        qvel: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let qpos = states(qpos, "qpos", self.model.nq(), f)?;
        let qvel = self.v(qvel, "qvel", f)?;
        run_with(
            py,
            self,
            &[&qpos, &qvel],
            &[self.model.nv()],
            f,
            |(), x, out| {
                out.copy_from_slice(&self.model.v_from_mujoco(x[0], x[1])?);
                Ok(())
            },
        )
    }

    /// kinetree's ``v`` at ``q`` as MuJoCo's ``qvel`` (the inverse of ``v_from_mujoco``).
    fn v_to_mujoco<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let (q, v) = (self.q(q, f)?, self.v(v, "v", f)?);
        run_with(py, self, &[&q, &v], &[self.model.nv()], f, |(), x, out| {
            out.copy_from_slice(&self.model.v_to_mujoco(x[0], x[1])?);
            Ok(())
        })
    }

    /// MuJoCo's ``qacc`` at ``qpos``, ``qvel`` as kinetree's ``a`` (for a free joint
    /// ``a_lin = Rᵀ qacc_lin − ω × v_lin``).
    fn a_from_mujoco<'py>(
        &self,
        py: Python<'py>,
        qpos: &Bound<'py, PyAny>,
        qvel: &Bound<'py, PyAny>,
        qacc: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let qpos = states(qpos, "qpos", self.model.nq(), f)?;
        let (qvel, qacc) = (self.v(qvel, "qvel", f)?, self.v(qacc, "qacc", f)?);
        run_with(
            py,
            self,
            &[&qpos, &qvel, &qacc],
            &[self.model.nv()],
            f,
            |(), x, out| {
                out.copy_from_slice(&self.model.a_from_mujoco(x[0], x[1], x[2])?);
                Ok(())
            },
        )
    }

    /// kinetree's ``a`` at ``q``, ``v`` as MuJoCo's ``qacc`` (the inverse of ``a_from_mujoco``).
    fn a_to_mujoco<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let (q, v, a) = (self.q(q, f)?, self.v(v, "v", f)?, self.v(a, "a", f)?);
        run_with(
            py,
            self,
            &[&q, &v, &a],
            &[self.model.nv()],
            f,
            |(), x, out| {
                out.copy_from_slice(&self.model.a_to_mujoco(x[0], x[1], x[2])?);
                Ok(())
            },
        )
    }

    /// MuJoCo generalized forces (``qfrc_*``) at ``qpos`` as kinetree's ``tau`` (a free
    /// joint's force goes from the world frame to the body frame; ``tau · v`` is unchanged).
    fn tau_from_mujoco<'py>(
        &self,
        py: Python<'py>,
        qpos: &Bound<'py, PyAny>,
        qfrc: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let qpos = states(qpos, "qpos", self.model.nq(), f)?;
        let qfrc = self.v(qfrc, "qfrc", f)?;
        run_with(
            py,
            self,
            &[&qpos, &qfrc],
            &[self.model.nv()],
            f,
            |(), x, out| {
                out.copy_from_slice(&self.model.tau_from_mujoco(x[0], x[1])?);
                Ok(())
            },
        )
    }

    /// kinetree's ``tau`` at ``q`` as MuJoCo generalized forces (the inverse of
    /// ``tau_from_mujoco``).
    fn tau_to_mujoco<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = Family::Model;
        let (q, tau) = (self.q(q, f)?, self.v(tau, "tau", f)?);
        run_with(
            py,
            self,
            &[&q, &tau],
            &[self.model.nv()],
            f,
            |(), x, out| {
                out.copy_from_slice(&self.model.tau_to_mujoco(x[0], x[1])?);
                Ok(())
            },
        )
    }
}
