//! `Model` methods of the dynamics layer: RNEA, CRBA, ABA, the inverse mass matrix, energies,
//! centre of mass, centroidal momentum and simulation. All are rigid-body dynamics (the joints'
//! damping, friction and armature left out), as Pinocchio computes them.

use crate::arrays::{
    ArrayPair, Count, Real, States, finite, in_block, reserve, run, run_blocks, states, to_numpy,
};
use crate::errors::{Family, py_err};
use crate::model::PyModel;
use crate::parts::{run_parts, run_parts_batched};
use crate::scratch::new_data;
use crate::values::Values;
use kinetree::dynamics::batch::{
    DerivativesBatch, aba_batch, aba_derivatives_batch, crba_batch, rnea_batch,
    rnea_derivatives_batch,
};
use kinetree::dynamics::{
    DynamicsData, Integrator, aba, aba_derivatives, center_of_mass, center_of_mass_jacobian,
    centroidal_momentum, crba, generalized_gravity, generalized_gravity_derivatives,
    kinetic_energy, mass_matrix_inverse, nonlinear_effects, potential_energy, rnea,
    rnea_derivatives, step,
};
use pyo3::prelude::*;

const F: Family = Family::Dynamics;

/// One derivative matrix (or a stack of them).
type Derivative<'py> = Bound<'py, numpy::PyArrayDyn<f64>>;

#[pymethods]
impl PyModel {
    /// Inverse dynamics (RNEA): the joint torques ``tau`` that give acceleration ``a`` at
    /// ``(q, v)`` under gravity. Shape ``(nv,)``, or ``(N, nv)`` for stacked inputs.
    ///
    /// ``out``, when given, is a C-contiguous, writeable float64 array of the result's shape: the
    /// torques are written into it and it is returned (as for every call with ``out``).
    ///
    /// >>> tau = panda.rnea(panda.neutral(), [0.0] * 9, [0.0] * 9)
    /// >>> bool(np.allclose(tau, panda.gravity(panda.neutral())))
    /// True
    /// >>> buffer = np.empty(9)
    /// >>> panda.rnea(panda.neutral(), [0.0] * 9, [0.0] * 9, out=buffer) is buffer
    /// True
    #[pyo3(signature = (q, v, a, out = None))]
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v, a) = (self.q(q, F)?, self.v(v, "v", F)?, self.v(a, "a", F)?);
        let nv = self.model.nv();
        let one = |d: &mut DynamicsData, x: &[&[f64]], out: &mut [f64]| {
            out.copy_from_slice(rnea(&self.model, d, x[0], x[1], x[2])?);
            Ok(())
        };
        run_blocks(
            py,
            self,
            &[&q, &v, &a],
            &[nv],
            out,
            F,
            one,
            |b, _, x, out| {
                rnea_batch(&self.model, b, x[0], x[1], x[2], out).map_err(|e| in_block(e.into()))
            },
        )
    }

    /// Nonlinear effects ``C(q, v) v + g(q)`` (RNEA with zero acceleration): shape ``(nv,)``.
    ///
    /// >>> q = panda.neutral()
    /// >>> bool(np.allclose(panda.nle(q, np.zeros(9)), panda.gravity(q)))
    /// True
    fn nle<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v) = (self.q(q, F)?, self.v(v, "v", F)?);
        run(py, self, &[&q, &v], &[self.model.nv()], F, |d, x, out| {
            out.copy_from_slice(nonlinear_effects(&self.model, d, x[0], x[1])?);
            Ok(())
        })
    }

    /// Generalized gravity ``g(q)``: the torques holding the robot still at ``q``.
    ///
    /// >>> arm = kinetree.Model.from_dh([[1.0, 0, 0, 0]])
    /// >>> arm.gravity([0.0])  # a massless arm
    /// array([0.])
    fn gravity<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        run(py, self, &[&q], &[self.model.nv()], F, |d, x, out| {
            out.copy_from_slice(generalized_gravity(&self.model, d, x[0])?);
            Ok(())
        })
    }

    /// The joint-space mass matrix ``M(q)`` (CRBA), full and symmetric: shape ``(nv, nv)``, or
    /// ``(N, nv, nv)``.
    ///
    /// ``out``: a float64 array of that shape to write ``M`` into, as for ``rnea``.
    ///
    /// >>> M = panda.crba(panda.neutral())
    /// >>> M.shape, bool((M == M.T).all())
    /// ((9, 9), True)
    /// >>> Ms = np.empty((4, 9, 9))
    /// >>> bool((panda.crba(panda.random_configuration(4, seed=1), out=Ms) == Ms).all())
    /// True
    #[pyo3(signature = (q, out = None))]
    fn crba<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        let nv = self.model.nv();
        let one = |d: &mut DynamicsData, x: &[&[f64]], out: &mut [f64]| {
            out.copy_from_slice(crba(&self.model, d, x[0])?);
            Ok(())
        };
        run_blocks(py, self, &[&q], &[nv, nv], out, F, one, |b, _, x, out| {
            crba_batch(&self.model, b, x[0], out).map_err(|e| in_block(e.into()))
        })
    }

    /// Forward dynamics (ABA): the acceleration ``a`` produced by torques ``tau`` at ``(q, v)``:
    /// shape ``(nv,)`` (or ``(N, nv)``); ``out`` as for ``rnea``.
    ///
    /// >>> q, v = panda.neutral(), np.zeros(9)
    /// >>> a = panda.aba(q, v, panda.gravity(q))  # holding torques: no acceleration
    /// >>> bool(np.allclose(a, 0.0, atol=1e-12))
    /// True
    /// >>> buffer = np.empty(9)
    /// >>> panda.aba(q, v, panda.gravity(q), out=buffer) is buffer
    /// True
    #[pyo3(signature = (q, v, tau, out = None))]
    fn aba<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v, t) = (self.q(q, F)?, self.v(v, "v", F)?, self.v(tau, "tau", F)?);
        let nv = self.model.nv();
        let one = |d: &mut DynamicsData, x: &[&[f64]], out: &mut [f64]| {
            out.copy_from_slice(aba(&self.model, d, x[0], x[1], x[2])?);
            Ok(())
        };
        run_blocks(
            py,
            self,
            &[&q, &v, &t],
            &[nv],
            out,
            F,
            one,
            |b, _, x, out| {
                aba_batch(&self.model, b, x[0], x[1], x[2], out).map_err(|e| in_block(e.into()))
            },
        )
    }

    /// The analytic derivatives of inverse dynamics ``tau = rnea(q, v, a)``: a tuple
    /// ``(dtau_dq, dtau_dv, M)``, each of shape ``(nv, nv)`` (``(N, nv, nv)`` for stacked
    /// inputs), ``M = ∂tau/∂a`` the mass matrix. ``dtau_dq`` is taken in the tangent space:
    /// column ``k`` is the derivative along ``integrate(q, eps * e_k)`` (a floating base moves
    /// along a body-frame twist, as in Pinocchio's ``computeRNEADerivatives``).
    ///
    /// >>> q, v, a = panda.neutral(), np.full(9, 0.3), np.zeros(9)
    /// >>> dtau_dq, dtau_dv, M = panda.rnea_derivatives(q, v, a)
    /// >>> dtau_dq.shape, bool(np.allclose(M, panda.crba(q)))
    /// ((9, 9), True)
    ///
    /// ``out``, when given, is a tuple of three separate C-contiguous, writeable float64 arrays of
    /// the results' shape: the matrices are written into them and they are returned (a loop then
    /// allocates nothing per call).
    ///
    /// >>> out = tuple(np.empty((9, 9)) for _ in range(3))
    /// >>> panda.rnea_derivatives(q, v, a, out=out)[2] is out[2]
    /// True
    #[pyo3(signature = (q, v, a, out = None))]
    fn rnea_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Derivative<'py>, Derivative<'py>, Derivative<'py>)> {
        let (q, v, a) = (self.q(q, F)?, self.v(v, "v", F)?, self.v(a, "a", F)?);
        let [dq, dv, da] = run_parts_batched(
            py,
            self,
            &[&q, &v, &a],
            out,
            F,
            |d, x| {
                let r = rnea_derivatives(&self.model, d, x[0], x[1], x[2])?;
                Ok([r.dtau_dq, r.dtau_dv, r.dtau_da])
            },
            |b: &mut DerivativesBatch, x, [dq, dv, da]| {
                rnea_derivatives_batch(&self.model, b, x[0], x[1], x[2], dq, dv, da)
                    .map_err(|e| in_block(e.into()))
            },
        )?;
        Ok((dq, dv, da))
    }

    /// The derivative ``∂g/∂q`` of the generalized gravity (tangent space, as
    /// ``rnea_derivatives``): shape ``(nv, nv)``, or ``(N, nv, nv)``.
    ///
    /// >>> q = panda.neutral()
    /// >>> bool(np.allclose(panda.gravity_derivatives(q), panda.rnea_derivatives(q, np.zeros(9), np.zeros(9))[0]))
    /// True
    ///
    /// ``out``: a float64 array of that shape to write the result into, as for ``rnea``.
    #[pyo3(signature = (q, out = None))]
    fn gravity_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Derivative<'py>> {
        let q = self.q(q, F)?;
        let [dg] = run_parts(py, self, &[&q], out, F, |d, x| {
            Ok([generalized_gravity_derivatives(&self.model, d, x[0])?])
        })?;
        Ok(dg)
    }

    /// The analytic derivatives of forward dynamics ``ddq = aba(q, v, tau)``: a tuple
    /// ``(dddq_dq, dddq_dv, Minv)``, each of shape ``(nv, nv)`` (or ``(N, nv, nv)``), ``Minv =
    /// ∂ddq/∂tau = M(q)⁻¹``; ``dddq_dq`` in the tangent space, as ``rnea_derivatives``.
    /// Computed from the inverse-dynamics derivatives at ``ddq`` and the tree-sparse
    /// factorization of ``M`` (as Pinocchio's ``computeABADerivatives``).
    ///
    /// >>> q, v = panda.neutral(), np.full(9, 0.3)
    /// >>> dddq_dq, dddq_dv, Minv = panda.aba_derivatives(q, v, np.zeros(9))
    /// >>> bool(np.allclose(Minv, panda.minv(q)))
    /// True
    ///
    /// ``out``: a tuple of three separate arrays to write the results into, as for
    /// ``rnea_derivatives``.
    #[pyo3(signature = (q, v, tau, out = None))]
    fn aba_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Derivative<'py>, Derivative<'py>, Derivative<'py>)> {
        let (q, v, t) = (self.q(q, F)?, self.v(v, "v", F)?, self.v(tau, "tau", F)?);
        let [dq, dv, dtau] = run_parts_batched(
            py,
            self,
            &[&q, &v, &t],
            out,
            F,
            |d, x| {
                let r = aba_derivatives(&self.model, d, x[0], x[1], x[2])?;
                Ok([r.dddq_dq, r.dddq_dv, r.dddq_dtau])
            },
            |b: &mut DerivativesBatch, x, [dq, dv, dtau]| {
                aba_derivatives_batch(&self.model, b, x[0], x[1], x[2], dq, dv, dtau)
                    .map_err(|e| in_block(e.into()))
            },
        )?;
        Ok((dq, dv, dtau))
    }

    /// The inverse mass matrix ``M(q)⁻¹``: shape ``(nv, nv)`` (or stacked).
    ///
    /// >>> q = panda.neutral()
    /// >>> bool(np.allclose(panda.minv(q) @ panda.crba(q), np.eye(9)))
    /// True
    fn minv<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        let nv = self.model.nv();
        run(py, self, &[&q], &[nv, nv], F, |d, x, out| {
            out.copy_from_slice(mass_matrix_inverse(&self.model, d, x[0])?);
            Ok(())
        })
    }

    /// Kinetic energy ``½ vᵀ M(q) v`` (J): a float, or shape ``(N,)``.
    ///
    /// >>> q = panda.neutral(); v = np.full(9, 0.1)
    /// >>> bool(np.isclose(panda.kinetic_energy(q, v), 0.5 * v @ panda.crba(q) @ v))
    /// True
    fn kinetic_energy<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v) = (self.q(q, F)?, self.v(v, "v", F)?);
        run(py, self, &[&q, &v], &[], F, |d, x, out| {
            out[0] = kinetic_energy(&self.model, d, x[0], x[1])?;
            Ok(())
        })
    }

    /// Potential energy in gravity (J, zero at the world origin): a float, or shape ``(N,)``.
    fn potential_energy<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        run(py, self, &[&q], &[], F, |d, x, out| {
            out[0] = potential_energy(&self.model, d, x[0])?;
            Ok(())
        })
    }

    /// Centre of mass in the world frame: shape ``(3,)`` (or ``(N, 3)``).
    ///
    /// >>> panda.com(panda.neutral()).shape
    /// (3,)
    fn com<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        run(py, self, &[&q], &[3], F, |d, x, out| {
            out.copy_from_slice(&center_of_mass(&self.model, d, x[0])?.to_array());
            Ok(())
        })
    }

    /// Jacobian of the centre of mass: shape ``(3, nv)`` (or stacked).
    fn com_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.q(q, F)?;
        let nv = self.model.nv();
        run(py, self, &[&q], &[3, nv], F, |d, x, out| {
            let cols = center_of_mass_jacobian(&self.model, d, x[0])?;
            for (k, c) in cols.iter().enumerate() {
                for r in 0..3 {
                    out[r * nv + k] = c[r];
                }
            }
            Ok(())
        })
    }

    /// Centroidal momentum at the centre of mass, world axes: shape ``(6,)``, linear then
    /// angular (or ``(N, 6)``).
    ///
    /// >>> panda.centroidal_momentum(panda.neutral(), np.zeros(9))
    /// array([0., 0., 0., 0., 0., 0.])
    fn centroidal_momentum<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v) = (self.q(q, F)?, self.v(v, "v", F)?);
        run(py, self, &[&q, &v], &[6], F, |d, x, out| {
            let h = centroidal_momentum(&self.model, d, x[0], x[1])?;
            out[..3].copy_from_slice(&h.linear.to_array());
            out[3..].copy_from_slice(&h.angular.to_array());
            Ok(())
        })
    }

    /// Simulates ``steps`` fixed steps of ``dt`` seconds from ``(q0, v0)`` under torques ``tau``
    /// (shape ``(nv,)`` held constant, or ``(steps, nv)``, default zero) with ``integrator``
    /// ``"rk4"`` or ``"euler"`` (semi-implicit). Returns ``(qs, vs)`` of shapes
    /// ``(steps + 1, nq)`` and ``(steps + 1, nv)``, the initial state first.
    ///
    /// >>> qs, vs = panda.simulate(panda.neutral(), np.zeros(9), dt=1e-3, steps=100)
    /// >>> qs.shape, vs.shape
    /// ((101, 9), (101, 9))
    #[pyo3(signature = (q0, v0, tau = None, dt = Real(1e-3), steps = Count::of(1000), integrator = "rk4"),
        text_signature = "($self, q0, v0, tau=None, dt=0.001, steps=1000, integrator=\"rk4\")")]
    #[allow(
        clippy::too_many_arguments,
        reason = "a Python signature with defaults"
    )]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        q0: &Bound<'py, PyAny>,
        v0: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        dt: Real,
        steps: Count,
        integrator: &str,
    ) -> PyResult<ArrayPair<'py>> {
        let (nq, nv) = (self.model.nq(), self.model.nv());
        let dt = finite(dt.0, "dt", F)?;
        let steps = steps.size("steps", F)?;
        let integrator = match integrator {
            "rk4" => Integrator::RungeKutta4,
            "euler" | "semi_implicit_euler" => Integrator::SemiImplicitEuler,
            other => {
                return Err(F.err(format!(
                    "integrator must be \"rk4\" or \"euler\", got {other:?}"
                )));
            }
        };
        let (q0, v0) = (self.q(q0, F)?, self.v(v0, "v0", F)?);
        if q0.count.is_some() || v0.count.is_some() {
            return Err(F.err("simulate takes one initial state: q0 (nq,) and v0 (nv,)"));
        }
        let tau: States = match tau {
            Some(t) => states(t, "tau", nv, F)?,
            None => States {
                values: Values::Owned(vec![0.0; nv]),
                width: nv,
                count: None,
                name: "tau",
                unchecked: false,
            },
        };
        if let Some(n) = tau.count
            && n != steps
        {
            return Err(F.err(format!(
                "tau stacks {n} rows but steps = {steps}: give one row per step or shape ({nv},)"
            )));
        }
        let model = &*self.model;
        // steps = 10**15 must be an error, not an aborted interpreter.
        let states = steps.checked_add(1);
        let mut qs = reserve(
            states.and_then(|n| n.checked_mul(nq)).unwrap_or(usize::MAX),
            "simulate's positions (steps + 1, nq)",
            F,
        )?;
        let mut vs = reserve(
            states.and_then(|n| n.checked_mul(nv)).unwrap_or(usize::MAX),
            "simulate's velocities (steps + 1, nv)",
            F,
        )?;
        let (qs, vs) = py
            .detach(|| {
                let mut data = new_data(model);
                let (mut q, mut v) = (q0.values.to_vec(), v0.values.to_vec());
                qs.extend_from_slice(&q);
                vs.extend_from_slice(&v);
                for i in 0..steps {
                    let t = tau.state(if tau.count.is_some() { i } else { 0 });
                    step(model, &mut data, integrator, &mut q, &mut v, t, dt)
                        .map_err(|e| (i, e))?;
                    qs.extend_from_slice(&q);
                    vs.extend_from_slice(&v);
                }
                Ok((qs, vs))
            })
            .map_err(|(i, e): (usize, kinetree::dynamics::DynamicsError)| {
                F.err(format!("step {i}: {}", py_err(e).value(py)))
            })?;
        Ok((
            to_numpy(py, &[steps + 1, nq], qs)?,
            to_numpy(py, &[steps + 1, nv], vs)?,
        ))
    }
}
