//! Joint position limits in a simulation: the inelastic hard stop on hand-worked cases and on the
//! Panda.

use kinetree_dynamics::kinematics::configuration::{clamp, is_within_limits};
use kinetree_dynamics::model::{Model, RootJoint};
use kinetree_dynamics::{
    DynamicsData, Integrator, apply_hard_stops, crba, limited_coordinates, mechanical_energy, step,
};

/// A 1 kg bob 0.5 m along x on a hinge about y (M = m·l² = 0.25 kg·m²), limits [-1, 1] rad.
fn pendulum() -> Model {
    Model::from_urdf_str(
        r#"<robot name="p"><link name="base"/>
      <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
        <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hinge" type="revolute"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#,
        RootJoint::Fixed,
    )
    .unwrap()
}

#[test]
fn a_stop_removes_the_outward_velocity_and_its_energy() {
    let model = pendulum();
    let mut data = DynamicsData::new(&model);
    assert_eq!(
        limited_coordinates(&model).collect::<Vec<_>>(),
        vec![(0, 0, -1.0, 1.0, 0)]
    );
    // Past the upper limit moving out at 2 rad/s: back on the limit, at rest, ½·0.25·2² = 0.5 J
    // lost.
    let (mut q, mut v) = (vec![1.2], vec![2.0]);
    let r = apply_hard_stops(&model, &mut data, &mut q, &mut v).unwrap();
    assert_eq!((q[0], v[0], r.stopped), (1.0, 0.0, 1));
    assert!((r.dissipated - 0.5).abs() < 1e-12, "{r:?}");
    // Past the lower limit but already moving back in: only the position is corrected.
    let (mut q, mut v) = (vec![-1.1], vec![0.3]);
    let r = apply_hard_stops(&model, &mut data, &mut q, &mut v).unwrap();
    assert_eq!((q[0], v[0], r.stopped, r.dissipated), (-1.0, 0.3, 1, 0.0));
    // Within the limits: nothing changes.
    let (mut q, mut v) = (vec![0.9], vec![5.0]);
    let r = apply_hard_stops(&model, &mut data, &mut q, &mut v).unwrap();
    assert_eq!((q[0], v[0], r.stopped), (0.9, 5.0, 0));
}

/// A planar two-link arm stopped at the shoulder: the impulse acts at the shoulder only, so
/// `M·Δv` is zero at the elbow, and the shoulder ends at rest.
#[test]
fn a_stop_couples_through_the_mass_matrix() {
    let model = Model::from_urdf_str(
        r#"<robot name="arm"><link name="base"/>
      <link name="upper"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
        <inertia ixx="0.01" iyy="0.05" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="fore"><inertial><origin xyz="0.4 0 0"/><mass value="1"/>
        <inertia ixx="0.01" iyy="0.03" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
        <limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
      <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="1 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
    </robot>"#,
        RootJoint::Fixed,
    )
    .unwrap();
    let mut data = DynamicsData::new(&model);
    let (mut q, mut v) = (vec![0.7, 0.3], vec![1.0, -0.5]);
    let v0 = v.clone();
    let r = apply_hard_stops(&model, &mut data, &mut q, &mut v).unwrap();
    assert_eq!((q[0], q[1], r.stopped), (0.5, 0.3, 1));
    assert!(v[0].abs() < 1e-15 && (v[1] - v0[1]).abs() > 1e-3, "{v:?}");
    let m = crba(&model, &mut data, &q).unwrap().to_vec();
    let dv = [v[0] - v0[0], v[1] - v0[1]];
    let elbow_impulse = m[2] * dv[0] + m[3] * dv[1];
    assert!(elbow_impulse.abs() < 1e-14, "{elbow_impulse}");
    let ke =
        |v: &[f64]| 0.5 * (v[0] * (m[0] * v[0] + m[1] * v[1]) + v[1] * (m[2] * v[0] + m[3] * v[1]));
    assert!((ke(&v0) - ke(&v) - r.dissipated).abs() < 1e-14);
    assert!(r.dissipated > 0.0);
}

/// The Panda falling under gravity for 1 s with stops after every step: every coordinate stays
/// within its limits. The stops' position correction (at most one step's overshoot) changes the
/// energy at first order in the time step: the energy gained over the run halves with the step.
/// Without the stops the fingers leave their 0.04 m range.
#[test]
fn the_panda_falls_within_its_limits_with_stops() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    let model = Model::from_urdf_file(path, RootJoint::Fixed).unwrap();
    let mut data = DynamicsData::new(&model);
    let start = {
        let mut q = vec![0.3, 0.5, -0.2, -1.5, 0.4, 1.8, 0.2, 0.02, 0.02];
        clamp(&model, &mut q).unwrap();
        q
    };
    let run = |data: &mut DynamicsData, stops: bool, dt: f64| -> (bool, f64) {
        let (mut q, mut v) = (start.clone(), vec![0.0; model.nv()]);
        let tau = vec![0.0; model.nv()];
        let mut e = mechanical_energy(&model, data, &q, &v).unwrap();
        let mut gained = 0.0f64;
        let mut within = true;
        for _ in 0..(1.0 / dt).round() as usize {
            step(
                &model,
                data,
                Integrator::RungeKutta4,
                &mut q,
                &mut v,
                &tau,
                dt,
            )
            .unwrap();
            if stops {
                apply_hard_stops(&model, data, &mut q, &mut v).unwrap();
            }
            within &= is_within_limits(&model, &q, 0.0).unwrap();
            let next = mechanical_energy(&model, data, &q, &v).unwrap();
            gained += (next - e).max(0.0);
            e = next;
        }
        (within, gained)
    };
    let mut gains = Vec::new();
    for dt in [2e-3, 1e-3, 5e-4] {
        let (within, gained) = run(&mut data, true, dt);
        assert!(within, "dt = {dt}");
        gains.push(gained);
    }
    eprintln!("energy gained by the stops at dt = 2, 1, 0.5 ms: {gains:?} J");
    assert!(
        gains[1] < 0.7 * gains[0] && gains[2] < 0.7 * gains[1],
        "{gains:?}"
    );
    let (within, _) = run(&mut data, false, 1e-3);
    assert!(!within, "the free fall was expected to break a limit");
}
