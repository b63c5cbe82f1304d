//! Helpers with the names [Exudyn](https://github.com/jgerstmayr/EXUDYN) users know from its
//! `exudyn.kinematicTree` and `exudyn.rigidBodyUtilities` Python modules (which follow
//! Featherstone's spatial algebra), for porting code and checking results side by side.
//!
//! Exudyn's 6x6 forms (`T66`) use **Featherstone's order `[angular; linear]`**, unlike the rest
//! of kinetree (`[linear; angular]`); the matrices returned here follow Exudyn. Inertia tensors
//! passed in or out are about the centre of mass, as in Exudyn. The joint-space functions use
//! kinetree's `q`/`v` layout (see the crate docs).
//!
//! | Exudyn | here |
//! |---|---|
//! | `MassCOMinertia2T66(mass, centerOfMass, inertia)` | [`mass_com_inertia_to_t66`] |
//! | `Inertia2T66(inertia)` | [`inertia_to_t66`] |
//! | `Inertia66toMassCOMinertia(inertia66)` | [`t66_to_mass_com_inertia`] |
//! | `RotationTranslation2T66(A, v)` | [`rotation_translation_to_t66`] |
//! | `T66toRotationTranslation(T66)` | [`t66_to_rotation_translation`] |
//! | `JointTransformMotionSubspace66(jointType, q)` | [`joint_transform_motion_subspace_66`] |
//! | `KinematicTree66.ComputeMassMatrixAndForceTerms(q, q_t, externalForces)` | [`compute_mass_matrix_and_force_terms`] |
//! | `KinematicTree66.ForwardDynamicsCRB(q, q_t, torques, forces)` | [`forward_dynamics_crb`] |
//! | `CRM(v)`, `CRF(v)` | [`crm`], [`crf`] |
//! | `KinematicTree33`'s `listOfInertia3D` (about the joint) ↔ inertia about the COM | [`tree33_inertia`], [`inertia_from_tree33`] |

use crate::data::DynamicsData;
use crate::error::{DynamicsError, check_vector};
use crate::external::ExternalForces;
use crate::rnea::{Output, check_inputs, sweep};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::glam::{DMat3, DVec3};
use kinetree_kinematics::spatial::{Inertia, Motion, Se3, rotation};
use kinetree_kinematics::{JointModel, KinematicsError};

/// A 6x6 matrix in Featherstone's `[angular; linear]` order, row-major (`m[row][col]`).
pub type T66 = [[f64; 6]; 6];

/// Reorders a `[linear; angular]` 6x6 matrix to `[angular; linear]` (and back).
fn swap_halves(m: &T66) -> T66 {
    let mut out = [[0.0; 6]; 6];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = m[(i + 3) % 6][(j + 3) % 6];
        }
    }
    out
}

/// Exudyn's `MassCOMinertia2T66`: the 6x6 spatial inertia, in Featherstone's `[angular; linear]`
/// order, of a body with `mass` (kg), centre of mass `com` (m, body frame) and rotational inertia
/// `inertia` about the centre of mass (kg·m², body axes):
/// `[[I + m·C·Cᵀ, m·C], [m·Cᵀ, m·1]]` with `C = [com]×`.
#[must_use]
#[doc(alias = "MassCOMinertia2T66")]
pub fn mass_com_inertia_to_t66(mass: f64, com: DVec3, inertia: DMat3) -> T66 {
    let c = rotation::skew(com);
    let top_left = inertia + c * c.transpose() * mass;
    let top_right = c * mass;
    let mut out = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = top_left.col(j)[i];
            out[i][j + 3] = top_right.col(j)[i];
            out[i + 3][j] = top_right.col(i)[j];
        }
        out[i + 3][i + 3] = mass;
    }
    out
}

/// Exudyn's `Inertia2T66`: the 6x6 form (`[angular; linear]`) of a kinetree [`Inertia`].
#[must_use]
#[doc(alias = "Inertia2T66")]
pub fn inertia_to_t66(inertia: &Inertia) -> T66 {
    mass_com_inertia_to_t66(inertia.mass, inertia.com, inertia.rotational.to_mat3())
}

/// Exudyn's `Inertia66toMassCOMinertia`: mass, centre of mass and rotational inertia about the
/// centre of mass from a 6x6 spatial inertia in `[angular; linear]` order. A zero mass gives a
/// zero centre of mass.
#[must_use]
#[doc(alias = "Inertia66toMassCOMinertia")]
pub fn t66_to_mass_com_inertia(t66: &T66) -> (f64, DVec3, DMat3) {
    let mass = t66[5][5];
    let mc = DMat3::from_cols(
        DVec3::new(t66[0][3], t66[1][3], t66[2][3]),
        DVec3::new(t66[0][4], t66[1][4], t66[2][4]),
        DVec3::new(t66[0][5], t66[1][5], t66[2][5]),
    );
    let top_left = DMat3::from_cols(
        DVec3::new(t66[0][0], t66[1][0], t66[2][0]),
        DVec3::new(t66[0][1], t66[1][1], t66[2][1]),
        DVec3::new(t66[0][2], t66[1][2], t66[2][2]),
    );
    if mass == 0.0 {
        return (0.0, DVec3::ZERO, top_left);
    }
    // Skew2Vec of m·[c]×.
    let com = DVec3::new(mc.y_axis.z, mc.z_axis.x, mc.x_axis.y) / mass;
    let inertia = top_left - mc * mc.transpose() * (1.0 / mass);
    (mass, com, inertia)
}

/// Exudyn's `RotationTranslation2T66`: the 6x6 Plücker motion transform `[[A, 0], [[v]×·A, A]]`
/// (`[angular; linear]`) of the frame with rotation `A` and translation `v`, i.e. of
/// `Se3::new(A, v).act_motion`.
#[must_use]
#[doc(alias = "RotationTranslation2T66")]
pub fn rotation_translation_to_t66(rotation: DMat3, translation: DVec3) -> T66 {
    swap_halves(&Se3::new(rotation, translation).to_action_matrix())
}

/// Exudyn's `T66toRotationTranslation`: the rotation and translation of a 6x6 Plücker motion
/// transform (`[angular; linear]`), inverse of [`rotation_translation_to_t66`].
#[must_use]
#[doc(alias = "T66toRotationTranslation")]
pub fn t66_to_rotation_translation(t66: &T66) -> (DMat3, DVec3) {
    let a = DMat3::from_cols(
        DVec3::new(t66[0][0], t66[1][0], t66[2][0]),
        DVec3::new(t66[0][1], t66[1][1], t66[2][1]),
        DVec3::new(t66[0][2], t66[1][2], t66[2][2]),
    );
    let ta = DMat3::from_cols(
        DVec3::new(t66[3][0], t66[4][0], t66[5][0]),
        DVec3::new(t66[3][1], t66[4][1], t66[5][1]),
        DVec3::new(t66[3][2], t66[4][2], t66[5][2]),
    );
    let t = ta * a.transpose();
    (a, DVec3::new(t.y_axis.z, t.z_axis.x, t.x_axis.y))
}

/// Exudyn's `CRM(v)`: Featherstone's 6x6 cross-product operator for motion vectors, in
/// `[angular; linear]` order: `crm(v)·m = v ×ₘ m`, i.e. `[[ω×, 0], [v×, ω×]]` for
/// `v = [ω; v]`.
#[must_use]
#[doc(alias = "CRM")]
pub fn crm(v: [f64; 6]) -> T66 {
    swap_halves(&Motion::from_featherstone(v).to_cross_motion_matrix())
}

/// Exudyn's `CRF(v)`: Featherstone's 6x6 cross-product operator for force vectors, in
/// `[angular; linear]` order: `crf(v)·f = v ×* f`, i.e. `[[ω×, v×], [0, ω×]] = -crm(v)ᵀ`.
#[must_use]
#[doc(alias = "CRF")]
pub fn crf(v: [f64; 6]) -> T66 {
    swap_halves(&Motion::from_featherstone(v).to_cross_force_matrix())
}

/// The rotational inertia about the body's reference point (its joint frame's origin) that
/// Exudyn's `KinematicTree33` takes as `listOfInertia3D`, from `mass`, the centre of mass `com`
/// (from the reference point, body axes) and the inertia about the centre of mass:
/// `I_ref = I_com + m·(|c|²·1 - c·cᵀ)` (parallel-axis theorem). It is the upper-left block of
/// [`mass_com_inertia_to_t66`].
#[must_use]
pub fn tree33_inertia(mass: f64, com: DVec3, inertia_about_com: DMat3) -> DMat3 {
    inertia_about_com + parallel_axis(mass, com)
}

/// The inverse of [`tree33_inertia`]: the inertia about the centre of mass from Exudyn's
/// `KinematicTree33` inertia about the reference point, its `listOfCOM` and `listOfMass`:
/// `I_com = I_ref - m·(|c|²·1 - c·cᵀ)`. With [`Inertia::new`] and a [`Symmetric3`] of it, a
/// `KinematicTree33` body becomes a kinetree inertia.
///
/// [`Symmetric3`]: kinetree_kinematics::spatial::Symmetric3
#[must_use]
pub fn inertia_from_tree33(mass: f64, com: DVec3, inertia_about_reference: DMat3) -> DMat3 {
    inertia_about_reference - parallel_axis(mass, com)
}

/// `m·(|c|²·1 - c·cᵀ)`: the inertia of a point mass `m` at `c` about the origin.
fn parallel_axis(mass: f64, c: DVec3) -> DMat3 {
    (DMat3::from_diagonal(DVec3::splat(c.length_squared()))
        - DMat3::from_cols(c * c.x, c * c.y, c * c.z))
        * mass
}

/// The joint transform and motion subspace of one joint, as Exudyn's
/// `JointTransformMotionSubspace66` returns them.
#[derive(Clone, Debug, PartialEq)]
pub struct JointTransformMotionSubspace66 {
    /// Featherstone's joint transform `XJ`: the Plücker transform (`[angular; linear]`) taking
    /// motion vectors from the joint's parent-side frame to the child frame (the inverse of the
    /// joint motion), as Exudyn's `RotationX2T66Inverse(q)` for `'Rx'`.
    pub transform: T66,
    /// The columns of the motion subspace `S` in the child frame (`[angular; linear]`), one per
    /// velocity coordinate (Exudyn's `MS` for 1-DoF joints).
    pub motion_subspace: Vec<[f64; 6]>,
}

/// Exudyn's `JointTransformMotionSubspace66`: the 6x6 joint transform and the motion subspace of
/// a joint (any kind, not only Exudyn's `'Rx'`…`'Pz'`) at its configuration block `q`. Get the
/// joint models from [`KinematicsData::joint_models`](kinetree_kinematics::KinematicsData) or
/// build one, e.g. `JointModel::RevoluteX`.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] when `q` is not the joint's configuration size;
/// [`DynamicsError::NonFinite`] for a NaN.
///
/// # Examples
/// ```
/// use kinetree_dynamics::exudyn::joint_transform_motion_subspace_66;
/// use kinetree_dynamics::kinematics::JointModel;
/// # fn main() -> Result<(), kinetree_dynamics::DynamicsError> {
/// let j = joint_transform_motion_subspace_66(&JointModel::RevoluteZ, &[0.5])?;
/// assert_eq!(j.motion_subspace, vec![[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]]);
/// // Rz(q)ᵀ in the angular block: row 0 is (cos q, sin q, 0).
/// assert!((j.transform[0][1] - 0.5f64.sin()).abs() < 1e-15);
/// # Ok(())
/// # }
/// ```
#[doc(alias = "JointTransformMotionSubspace66")]
pub fn joint_transform_motion_subspace_66(
    joint: &JointModel,
    q: &[f64],
) -> Result<JointTransformMotionSubspace66, DynamicsError> {
    let nq = joint.nq();
    check_vector("q", q, nq)?;
    if let JointModel::Spherical | JointModel::Floating = joint {
        let r = &q[nq - 4..];
        let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > kinetree_kinematics::QUATERNION_NORM_TOLERANCE {
            return Err(KinematicsError::NonUnitQuaternion {
                joint: format!("{joint:?}"),
                norm,
            }
            .into());
        }
    }
    Ok(JointTransformMotionSubspace66 {
        transform: swap_halves(&joint.transform(q).inverse().to_action_matrix()),
        motion_subspace: (0..joint.nv())
            .map(|k| joint.subspace_column(k).to_featherstone())
            .collect(),
    })
}

/// Exudyn's `ComputeMassMatrixAndForceTerms`: the mass matrix `M(q)` and the force terms
/// `f(q, q̇, f_ext)` of the equations of motion `M(q)·q̈ + f(q, q̇, f_ext) = τ`.
///
/// `f` collects Coriolis, centrifugal and gravity torques, minus the generalized forces of the
/// external wrenches `fext` (plus the joints' damping and friction with
/// [`JointTerms::FromModel`](crate::JointTerms::FromModel)). `M` is `nv x nv` row-major, stored
/// in [`DynamicsData::mass_matrix`]; `f` (length `nv`) is stored in [`DynamicsData::nle`].
/// Allocates nothing.
///
/// # Errors
/// As [`rnea_with_external_forces`](crate::rnea_with_external_forces).
#[doc(alias = "ComputeMassMatrixAndForceTerms")]
pub fn compute_mass_matrix_and_force_terms<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    fext: &ExternalForces,
) -> Result<(&'d [f64], &'d [f64]), DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    fext.check_model(model)?;
    crate::crba::compute(model, data, q);
    sweep::<true, false>(model, data, q, v, &[], Some(fext), Output::Nle);
    Ok((&data.mass_matrix, &data.nle))
}

/// Exudyn's `ForwardDynamicsCRB(q, q_t, torques=[], forces=[])`: forward dynamics through the
/// mass matrix, `q̈ = M(q)⁻¹·(τ - f(q, q̇, f_ext))`, with [`crba`](crate::crba), the tree-sparse
/// factorization ([`factorize_mass_matrix`](crate::factorize_mass_matrix)) and the force terms of
/// [`compute_mass_matrix_and_force_terms`]. `tau: None` means zero joint torques; `fext` are
/// wrenches on links, in the frame each was added in (Exudyn gives them in the world frame:
/// [`ReferenceFrame::World`](crate::ReferenceFrame::World)) — where Exudyn's own Python
/// implementation raises "forces not implemented". Gives the same result as
/// [`aba_with_external_forces`](crate::aba_with_external_forces) (which is faster for one call);
/// the factorization stays in `data` for more solves. Stored in [`DynamicsData::ddq`] and
/// returned. Allocates nothing.
///
/// # Errors
/// As [`aba`](crate::aba); [`DynamicsError::DataMismatch`] when `fext` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::exudyn::forward_dynamics_crb;
/// use kinetree_dynamics::model::{Model, RootJoint};
/// use kinetree_dynamics::spatial::{glam::DVec3, Force};
/// use kinetree_dynamics::{DynamicsData, ExternalForces, FrameId, ReferenceFrame};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg slider along world x, pushed by 3 N in the world frame: 3 m/s².
/// let model = Model::from_urdf_str(r#"<robot name="s"><link name="rail"/>
///   <link name="cart"><inertial><mass value="1"/>
///     <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="x" type="prismatic"><parent link="rail"/><child link="cart"/><axis xyz="1 0 0"/>
///     <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// let mut fext = ExternalForces::new(&model);
/// let cart = FrameId::find(&model, "cart")?;
/// fext.add(&model, cart, ReferenceFrame::World, Force::new(DVec3::new(3.0, 0.0, 0.0), DVec3::ZERO))?;
/// let ddq = forward_dynamics_crb(&model, &mut data, &[0.0], &[0.0], None, Some(&fext))?;
/// assert!((ddq[0] - 3.0).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
#[doc(alias = "ForwardDynamicsCRB")]
pub fn forward_dynamics_crb<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: Option<&[f64]>,
    fext: Option<&ExternalForces>,
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    if let Some(tau) = tau {
        check_vector("tau", tau, model.nv())?;
    }
    if let Some(fext) = fext {
        fext.check_model(model)?;
    }
    crate::crba::compute(model, data, q);
    crate::factor::factorize(model, data)?;
    sweep::<true, false>(model, data, q, v, &[], fext, Output::Nle);
    for (k, (x, n)) in data.ddq.iter_mut().zip(&data.nle).enumerate() {
        *x = tau.map_or(0.0, |t| t[k]) - n;
    }
    crate::factor::solve_in_place(&data.factor, &mut data.ddq);
    Ok(&data.ddq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_kinematics::spatial::Symmetric3;

    #[test]
    fn t66_round_trips() {
        let inertia = Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        );
        let t = inertia_to_t66(&inertia);
        // Same matrix as kinetree's own [linear; angular] form, halves swapped.
        let own = swap_halves(&inertia.to_matrix());
        for i in 0..6 {
            for j in 0..6 {
                assert!((t[i][j] - own[i][j]).abs() < 1e-14);
            }
        }
        let (m, c, i3) = t66_to_mass_com_inertia(&t);
        assert!((m - 2.5).abs() < 1e-15);
        assert!((c - inertia.com).length() < 1e-14);
        assert!(i3.abs_diff_eq(inertia.rotational.to_mat3(), 1e-14));
        let x = Se3::from_xyz_rpy([0.5, 1.0, -0.3], [0.2, 0.4, -0.8]);
        let (r, p) =
            t66_to_rotation_translation(&rotation_translation_to_t66(x.rotation, x.translation));
        assert!(r.abs_diff_eq(x.rotation, 1e-15) && (p - x.translation).length() < 1e-14);
    }

    #[test]
    fn joint_transform_is_featherstone_rotx() {
        let q = 0.7;
        let j = joint_transform_motion_subspace_66(&JointModel::RevoluteX, &[q]).expect("1 dof");
        let (s, c) = q.sin_cos();
        // Featherstone's rotx(q): E = [[1, 0, 0], [0, c, s], [0, -s, c]] on both diagonal blocks.
        let e = [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]];
        for i in 0..3 {
            for k in 0..3 {
                assert!((j.transform[i][k] - e[i][k]).abs() < 1e-15);
                assert!((j.transform[i + 3][k + 3] - e[i][k]).abs() < 1e-15);
                assert!(j.transform[i][k + 3].abs() < 1e-15);
                assert!(j.transform[i + 3][k].abs() < 1e-15);
            }
        }
        assert_eq!(j.motion_subspace, vec![[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]);
        let p = joint_transform_motion_subspace_66(&JointModel::PrismaticY, &[0.3]).expect("1 dof");
        // Featherstone's xlt(r) with r = (0, 0.3, 0): lower-left block -[r]×.
        assert!((p.transform[3][2] + 0.3).abs() < 1e-15 && (p.transform[5][0] - 0.3).abs() < 1e-15);
        assert!(matches!(
            joint_transform_motion_subspace_66(&JointModel::Floating, &[0.0; 6]),
            Err(DynamicsError::DimensionMismatch { .. })
        ));
    }
}
