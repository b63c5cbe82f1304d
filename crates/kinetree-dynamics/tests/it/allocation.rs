//! The hot paths allocate nothing once the data exists: a counting global allocator for this
//! test binary (`kinetree-test-support`) counts allocations made by the current thread.

use crate::common::{all_models, random_state, rng};
use kinetree_dynamics::spatial::Force;
use kinetree_dynamics::spatial::glam::DVec3;
use kinetree_dynamics::{
    DynamicsData, ExternalForces, FrameId, Integrator, JointTerms, ReferenceFrame, aba,
    aba_with_external_forces, center_of_mass, center_of_mass_jacobian, center_of_mass_velocity,
    centroidal_momentum, crba, exudyn, factorize_mass_matrix, generalized_gravity, kinetic_energy,
    mass_matrix_inverse, mechanical_energy, nonlinear_effects, potential_energy, rnea,
    rnea_with_external_forces, solve_mass_matrix, step, step_with_external_forces,
};
use kinetree_test_support::{CountingAllocator, allocations_during};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn hot_paths_do_not_allocate() {
    for (name, model) in all_models() {
        let (q, v, a) = random_state(&model, &mut rng(7));
        let mut data = DynamicsData::new(&model);
        let mut fext = ExternalForces::new(&model);
        let last = FrameId::Link(model.links().len() - 1);
        let mut rhs = vec![0.5; 3 * model.nv()];
        let (mut qs, mut vs) = (q.clone(), v.clone());
        let tau = vec![0.1; model.nv()];
        let count = allocations_during(|| {
            for _ in 0..3 {
                fext.clear();
                let f = Force::new(DVec3::X, DVec3::Y);
                for reference in [
                    ReferenceFrame::Local,
                    ReferenceFrame::World,
                    ReferenceFrame::LocalWorldAligned,
                ] {
                    fext.add(&model, last, reference, f).unwrap();
                }
                rnea(&model, &mut data, &q, &v, &a).unwrap();
                rnea_with_external_forces(&model, &mut data, &q, &v, &a, &fext).unwrap();
                nonlinear_effects(&model, &mut data, &q, &v).unwrap();
                generalized_gravity(&model, &mut data, &q).unwrap();
                crba(&model, &mut data, &q).unwrap();
                factorize_mass_matrix(&model, &mut data, &q).unwrap();
                solve_mass_matrix(&model, &mut data, &mut rhs).unwrap();
                mass_matrix_inverse(&model, &mut data, &q).unwrap();
                aba(&model, &mut data, &q, &v, &tau).unwrap();
                aba_with_external_forces(&model, &mut data, &q, &v, &tau, &fext).unwrap();
                exudyn::forward_dynamics_crb(&model, &mut data, &q, &v, Some(&tau), Some(&fext))
                    .unwrap();
                exudyn::compute_mass_matrix_and_force_terms(&model, &mut data, &q, &v, &fext)
                    .unwrap();
                kinetic_energy(&model, &mut data, &q, &v).unwrap();
                potential_energy(&model, &mut data, &q).unwrap();
                mechanical_energy(&model, &mut data, &q, &v).unwrap();
                center_of_mass(&model, &mut data, &q).unwrap();
                center_of_mass_velocity(&model, &mut data, &q, &v).unwrap();
                center_of_mass_jacobian(&model, &mut data, &q).unwrap();
                centroidal_momentum(&model, &mut data, &q, &v).unwrap();
                for integrator in [Integrator::SemiImplicitEuler, Integrator::RungeKutta4] {
                    step(&model, &mut data, integrator, &mut qs, &mut vs, &tau, 1e-4).unwrap();
                    step_with_external_forces(
                        &model, &mut data, integrator, &mut qs, &mut vs, &tau, 1e-4, &fext,
                    )
                    .unwrap();
                }
                data.set_joint_terms(&model, JointTerms::Ignored).unwrap();
                data.set_joint_terms(&model, JointTerms::FromModel).unwrap();
            }
        });
        assert_eq!(count, 0, "{name}: the dynamics hot paths allocated");
    }
}

#[test]
fn derivatives_do_not_allocate() {
    use kinetree_dynamics::kinematics::{
        KinematicsDerivativesData, difference_jacobians, frame_acceleration_derivatives,
        frame_jacobian_derivatives, frame_velocity_derivatives, integrate_jacobians,
    };
    use kinetree_dynamics::{
        DerivativesData, aba_derivatives, aba_derivatives_with_external_forces,
        generalized_gravity_derivatives, rnea_derivatives, rnea_derivatives_with_external_forces,
    };
    for (name, model) in all_models() {
        let (q, v, a) = random_state(&model, &mut rng(8));
        let mut data = DerivativesData::with_joint_terms(&model, JointTerms::FromModel);
        let mut fext = ExternalForces::new(&model);
        let last = FrameId::Link(model.links().len() - 1);
        let tau = vec![0.1; model.nv()];
        let nv = model.nv();
        let mut kd = KinematicsDerivativesData::new(&model);
        let mut m = vec![vec![0.0; 6 * nv]; 4];
        let mut hessian = vec![0.0; 6 * nv * nv];
        let (mut j0, mut j1) = (vec![0.0; nv * nv], vec![0.0; nv * nv]);
        let count = allocations_during(|| {
            for _ in 0..3 {
                fext.clear();
                for reference in [
                    ReferenceFrame::Local,
                    ReferenceFrame::World,
                    ReferenceFrame::LocalWorldAligned,
                ] {
                    fext.add(&model, last, reference, Force::new(DVec3::X, DVec3::Y))
                        .unwrap();
                    let [m0, m1, m2, m3] = &mut m[..] else {
                        unreachable!()
                    };
                    frame_velocity_derivatives(&model, &mut kd, &q, &v, last, reference, m0, m1)
                        .unwrap();
                    frame_acceleration_derivatives(
                        &model, &mut kd, &q, &v, &a, last, reference, m0, m1, m2, m3,
                    )
                    .unwrap();
                    frame_jacobian_derivatives(&model, &mut kd, &q, last, reference, &mut hessian)
                        .unwrap();
                }
                integrate_jacobians(&model, &q, &v, &mut j0, &mut j1).unwrap();
                difference_jacobians(&model, &q, &q, &mut j0, &mut j1).unwrap();
                rnea_derivatives(&model, &mut data, &q, &v, &a).unwrap();
                rnea_derivatives_with_external_forces(&model, &mut data, &q, &v, &a, &fext)
                    .unwrap();
                generalized_gravity_derivatives(&model, &mut data, &q).unwrap();
                aba_derivatives(&model, &mut data, &q, &v, &tau).unwrap();
                aba_derivatives_with_external_forces(&model, &mut data, &q, &v, &tau, &fext)
                    .unwrap();
            }
        });
        assert_eq!(count, 0, "{name}: the derivatives allocated");
    }
}

#[test]
fn batched_algorithms_do_not_allocate() {
    use kinetree_dynamics::batch::{DynamicsBatch, aba_batch, crba_batch, rnea_batch};
    use kinetree_dynamics::kinematics::batch::{
        KinematicsBatch, forward_kinematics_batch, frame_jacobian_batch,
    };
    use kinetree_dynamics::spatial::{Motion, Se3};
    for (name, model) in all_models() {
        let n = 11;
        let (nq, nv) = (model.nq(), model.nv());
        let mut r = rng(9);
        let (mut q, mut v, mut a) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..n {
            let (qk, vk, ak) = random_state(&model, &mut r);
            q.extend(qk);
            v.extend(vk);
            a.extend(ak);
        }
        assert_eq!(q.len(), n * nq);
        let mut kb = KinematicsBatch::new(&model);
        let mut db = DynamicsBatch::new(&model);
        let mut links = vec![Se3::IDENTITY; n * model.links().len()];
        let mut frames = vec![Se3::IDENTITY; n * model.frames().len()];
        let mut jac = vec![Motion::ZERO; n * nv];
        let mut out = vec![0.0; n * nv];
        let mut mass = vec![0.0; n * nv * nv];
        let last = FrameId::Link(model.links().len() - 1);
        let count = allocations_during(|| {
            for _ in 0..2 {
                forward_kinematics_batch(&model, &mut kb, &q, &mut links, Some(&mut frames))
                    .unwrap();
                frame_jacobian_batch(&model, &mut kb, &q, last, ReferenceFrame::World, &mut jac)
                    .unwrap();
                rnea_batch(&model, &mut db, &q, &v, &a, &mut out).unwrap();
                aba_batch(&model, &mut db, &q, &v, &a, &mut out).unwrap();
                crba_batch(&model, &mut db, &q, &mut mass).unwrap();
            }
        });
        assert_eq!(count, 0, "{name}: the batched algorithms allocated");
    }
}

#[test]
fn batched_derivatives_do_not_allocate() {
    use kinetree_dynamics::batch::{
        DerivativesBatch, aba_derivatives_batch, rnea_derivatives_batch,
    };
    for (name, model) in all_models() {
        let n = 11;
        let nn = model.nv() * model.nv();
        let mut r = rng(10);
        let (mut q, mut v, mut a) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..n {
            let (qk, vk, ak) = random_state(&model, &mut r);
            q.extend(qk);
            v.extend(vk);
            a.extend(ak);
        }
        let mut batch = DerivativesBatch::new(&model);
        let (mut dq, mut dv, mut da) = (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
        let (mut ddq, mut ddv, mut minv) =
            (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
        let count = allocations_during(|| {
            for _ in 0..2 {
                rnea_derivatives_batch(&model, &mut batch, &q, &v, &a, &mut dq, &mut dv, &mut da)
                    .unwrap();
                // `a` serves as the torques.
                aba_derivatives_batch(
                    &model, &mut batch, &q, &v, &a, &mut ddq, &mut ddv, &mut minv,
                )
                .unwrap();
            }
        });
        assert_eq!(count, 0, "{name}: the batched derivatives allocated");
        assert!(da.iter().any(|&x| x != 0.0), "{name}: nothing computed");
        assert!(minv.iter().any(|&x| x != 0.0), "{name}: nothing computed");
    }
}
