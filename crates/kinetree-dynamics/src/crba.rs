//! The joint-space mass matrix: the composite rigid-body algorithm.

use crate::data::{AncestorStep, DynamicsData};
use crate::error::DynamicsError;
use crate::rnea::check_inputs;
use core::ops::{Index, IndexMut};
use kinetree_kinematics::JointModel;
use kinetree_kinematics::joint::JointRot;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::real::{Matrix3 as _, Real, Vector3 as _};
use kinetree_kinematics::spatial::{Force, Motion, OriginInertia, RotationForm, Se3};

/// The joint-space mass (inertia) matrix `M(q)`: `nv x nv`, symmetric positive (semi-)definite,
/// with `½·q̇ᵀ·M·q̇` the kinetic energy.
///
/// `q` has length `model.nq()`. The full symmetric matrix is stored row-major in
/// [`DynamicsData::mass_matrix`] (`m[i * nv + j]`) and returned. With
/// [`JointTerms::FromModel`] the joints' armature is added to the diagonal. Entries of two
/// joints on different branches (neither an ancestor of the other) are zero.
///
/// Composite rigid-body algorithm in body-local coordinates (Featherstone's CRBA; Pinocchio ≥ 3's
/// default `Convention::LOCAL`): O(n·depth), allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q`;
/// [`DynamicsError::DataMismatch`] when `data` belongs to another model.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{crba, DynamicsData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let urdf = r#"<robot name="pendulum"><link name="base"/>
///   <link name="bob"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
///     <inertia ixx="0" iyy="0.1" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
///   <joint name="hinge" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// let m = crba(&model, &mut data, &[0.3])?;
/// // I_yy + m·l² = 0.1 + 2·0.25.
/// assert!((m[0] - 0.6).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
///
/// [`JointTerms::FromModel`]: crate::JointTerms::FromModel
#[doc(alias = "mass_matrix")]
#[doc(alias = "inertia_matrix")]
#[doc(alias = "joint_space_inertia_matrix")]
pub fn crba<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    let probe = compute(model, data, q);
    // Every entry the sweep writes went into `probe` (the others stay 0): a finite probe
    // proves the matrix finite without reading it again.
    if !probe.is_finite() {
        check_mass_matrix(model, data)?;
    }
    Ok(&data.mass_matrix)
}

/// The output check of [`crba`] when the sweep's probe is not finite: every entry of the mass
/// matrix is finite. The entries are
/// summed in eight independent lanes (a non-finite entry makes the sum non-finite), which is a
/// few vector additions per row; only a sum that is not finite (a bad entry, or finite entries
/// whose sum overflows) searches for the entry to name.
fn check_mass_matrix(model: &Model, data: &DynamicsData) -> Result<(), DynamicsError> {
    let m = &data.mass_matrix;
    let mut acc = [0.0f64; 8];
    let mut chunks = m.chunks_exact(8);
    for c in &mut chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            *a += x;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += x;
    }
    if acc.iter().sum::<f64>().is_finite() {
        return Ok(());
    }
    crate::error::check_output(model, data, "mass matrix", m)
}

/// The CRBA sweeps of one state (inputs already checked): the generic [`place`] and [`sweep`]
/// on `f64`, into [`DynamicsData::mass_matrix`]. Returns the sweep's probe: the sum of every
/// entry written once (each lower-triangle entry and the diagonal, armature included), finite
/// exactly when those entries are, unless finite entries overflow the sum.
pub(crate) fn compute(model: &Model, data: &mut DynamicsData, q: &[f64]) -> f64 {
    // Not through `with_simd!` as the RNEA sweep: compiled for AVX-512 this sweep was 5–10 %
    // slower (`kinetree bench`, panda, ur5, kinova, talos_reduced).
    let kin = data.kinematics.body_buffers_mut();
    kin.q.copy_from_slice(q);
    let tree = Tree {
        model,
        joint_models: kin.joint_models,
        steps: &data.ancestor_step,
        body_inertia: &data.body_inertia,
        placement_rot: &data.placement_rot,
        armature: data.has_joint_terms.then_some(&data.armature[..]),
    };
    place(&tree, q, &mut *kin.parent_from_body, &mut data.joint_rot);
    let mut out = Dense {
        m: &mut data.mass_matrix,
        nv: data.nv,
    };
    sweep(
        &tree,
        &*kin.parent_from_body,
        &data.joint_rot,
        &mut data.composite,
        &mut out,
    )
}

/// What the CRBA sweeps read: the model's bodies and joint models, and the constants the data
/// keeps per body.
pub(crate) struct Tree<'a> {
    pub(crate) model: &'a Model,
    pub(crate) joint_models: &'a [JointModel],
    pub(crate) steps: &'a [AncestorStep],
    /// Each body's own inertia about its origin.
    pub(crate) body_inertia: &'a [OriginInertia],
    /// The form of each body's placement rotation.
    pub(crate) placement_rot: &'a [RotationForm],
    /// The armature per degree of freedom, when the joint terms are included.
    pub(crate) armature: Option<&'a [f64]>,
}

impl<'a> Tree<'a> {
    /// The sweeps' view of `model` and `data`.
    pub(crate) fn of(model: &'a Model, data: &'a DynamicsData) -> Self {
        Self {
            model,
            joint_models: data.kinematics.joint_models(),
            steps: &data.ancestor_step,
            body_inertia: &data.body_inertia,
            placement_rot: &data.placement_rot,
            armature: data.has_joint_terms.then_some(&data.armature[..]),
        }
    }
}

/// Where the CRBA sweep's entries go, in the order it computes them: a matrix of one state,
/// or the lane buffers of a block of states.
pub(crate) trait Entries<T: Real> {
    /// Entry `(r, c)` and its mirror `(c, r)`.
    fn put(&mut self, r: usize, c: usize, x: T);
    /// Adds `x` to diagonal entry `k` (after every [`Entries::put`]) and returns the sum.
    fn add_diagonal(&mut self, k: usize, x: f64) -> T;
}

/// The row-major `nv x nv` matrix of one state.
struct Dense<'a> {
    m: &'a mut [f64],
    nv: usize,
}

impl Entries<f64> for Dense<'_> {
    #[inline(always)]
    fn put(&mut self, r: usize, c: usize, x: f64) {
        self.m[r * self.nv + c] = x;
        self.m[c * self.nv + r] = x;
    }

    #[inline(always)]
    fn add_diagonal(&mut self, k: usize, x: f64) -> f64 {
        let d = &mut self.m[k * self.nv + k];
        *d += x;
        *d
    }
}

/// Each body's placement `parent_from_body` and, for a revolute joint about a coordinate axis,
/// the joint's rotation apart (for [`JointModel::inertia_to_parent`]); written once for one
/// state and for lanes.
#[inline(always)]
pub(crate) fn place<T: Real>(
    tree: &Tree<'_>,
    q: &[T],
    parent_from_body: &mut (impl IndexMut<usize, Output = Se3<T>> + ?Sized),
    joint_rot: &mut (impl IndexMut<usize, Output = JointRot<T>> + ?Sized),
) {
    for (i, b) in tree.model.bodies().iter().enumerate().skip(1) {
        let (x, jr) = tree.joint_models[i]
            .placed_transform_factored(&b.placement, &q[b.idx_q..b.idx_q + b.nq]);
        parent_from_body[i].assign(&x);
        joint_rot[i] = jr;
    }
}

/// The composite rigid-body sweep, written once for one state and for lanes: body-local
/// composite inertias (Pinocchio's `Convention::LOCAL`); each body's force columns `Icᵢ·Sᵢ` are
/// carried up to every ancestor, and each composite inertia moves to its parent with the joint
/// and placement rotations in their cheap forms (a few multiplications for axis-aligned joints
/// and placements). The entries go to `out` (bodies from last to first; each body's diagonal
/// block, then its rows of each ancestor from the parent up), then the armature. Returns the
/// sum of the entries (the output check's probe).
#[inline(always)]
pub(crate) fn sweep<T: Real>(
    tree: &Tree<'_>,
    parent_from_body: &(impl Index<usize, Output = Se3<T>> + ?Sized),
    joint_rot: &(impl Index<usize, Output = JointRot<T>> + ?Sized),
    composite: &mut (impl IndexMut<usize, Output = OriginInertia<T>> + ?Sized),
    out: &mut impl Entries<T>,
) -> T {
    let bodies = tree.model.bodies();
    let (joint_models, steps) = (tree.joint_models, tree.steps);
    // Scratch for multi-DoF joints, each entry written before it is read.
    let mut f = [Force::<T>::zero(); 6];
    let mut col = [T::ZERO; 6];
    let mut probe = T::ZERO;
    // One state: the composite inertia just written and its body, which in a chain is the next
    // body's, read from registers. Read back from memory, its 16-byte loads straddled the
    // stores of the addition and stalled store forwarding twice a body (one-state CRBA 5–11 %
    // slower). Lanes store and load whole vectors, and copy nothing extra.
    let mut carried: Option<(usize, OriginInertia<T>)> = None;
    for i in (1..bodies.len()).rev() {
        let b = &bodies[i];
        let (iv, ni) = (b.idx_v, b.nv);
        // A leaf's composite inertia is its own; the others were started by their last child.
        let ic = if steps[i].leaf {
            OriginInertia::from_const(&tree.body_inertia[i])
        } else if let Some((k, c)) = carried
            && k == i
        {
            c
        } else {
            composite[i]
        };
        // F = Icᵢ·Sᵢ and the diagonal block Sᵢᵀ·Icᵢ·Sᵢ.
        let jm = &joint_models[i];
        let f0 = match jm.axis_momentum(&ic) {
            Some(f0) => f0,
            None => {
                for k in 0..ni {
                    f[k] = ic.mul_motion(&Motion::from_const(&jm.subspace_column(k)));
                }
                for k in 0..ni {
                    jm.project_force(&f[k], &mut col[..ni]);
                    for l in k..ni {
                        probe += col[l];
                        out.put(iv + l, iv + k, col[l]);
                    }
                }
                f[0]
            }
        };
        if ni == 1 {
            // The common case, one column: carry it up to every ancestor.
            let mut fk = f0;
            if let Some(d) = jm.project_axis(&fk) {
                probe += d;
                out.put(iv, iv, d);
            }
            let mut j = i;
            loop {
                let step = steps[j];
                if step.parent == 0 {
                    break;
                }
                let x = &parent_from_body[j];
                let jv = step.parent_v;
                if step.last {
                    // The last ancestor, about or along a coordinate axis: only its component
                    // of the moved force is needed.
                    let v = axis_component_of(x, &fk, step.kind);
                    probe += v;
                    out.put(jv, iv, v);
                    break;
                }
                fk = x.act_force(&fk);
                j = step.parent;
                if step.kind < AncestorStep::FLOATING {
                    let v = component(&fk, step.kind);
                    probe += v;
                    out.put(jv, iv, v);
                } else {
                    let nj = bodies[j].nv;
                    if step.kind == AncestorStep::FLOATING {
                        // A floating base's rows are the wrench itself (inlined: every
                        // column of a floating-base robot ends here).
                        for l in 0..3 {
                            col[l] = fk.linear.get(l);
                            col[l + 3] = fk.angular.get(l);
                        }
                    } else {
                        joint_models[j].project_force(&fk, &mut col[..nj]);
                    }
                    for l in 0..nj {
                        probe += col[l];
                        out.put(jv + l, iv, col[l]);
                    }
                }
            }
        } else {
            let mut j = i;
            loop {
                let p = bodies[j].parent;
                if p == 0 {
                    break;
                }
                for fk in f[..ni].iter_mut() {
                    *fk = parent_from_body[j].act_force(fk);
                }
                j = p;
                let (jv, nj) = (bodies[j].idx_v, bodies[j].nv);
                for k in 0..ni {
                    joint_models[j].project_force(&f[k], &mut col[..nj]);
                    for l in 0..nj {
                        probe += col[l];
                        out.put(jv + l, iv + k, col[l]);
                    }
                }
            }
        }
        if b.parent != 0 {
            let moved = jm.inertia_to_parent(
                &ic,
                joint_rot[i],
                &tree.placement_rot[i],
                &parent_from_body[i],
            );
            let mut c = if steps[i].opens_parent {
                OriginInertia::from_const(&tree.body_inertia[b.parent])
            } else {
                composite[b.parent]
            };
            c.add_assign(&moved);
            composite[b.parent] = c;
            if T::LANES == 1 {
                carried = Some((b.parent, c));
            }
        }
    }
    if let Some(armature) = tree.armature {
        for (k, a) in armature.iter().enumerate() {
            probe += out.add_diagonal(k, *a);
        }
    }
    probe
}

/// Component `c` of a force in `[linear; angular]` order (`c < 6`), as
/// [`JointModel::project_axis`] reads it.
#[inline(always)]
fn component<T: Real>(f: &Force<T>, c: u8) -> T {
    if c < 3 {
        f.linear.get(usize::from(c))
    } else {
        f.angular.get(usize::from(c - 3))
    }
}

/// Row `i` of `R·v`, summed as `DMat3 * DVec3` sums its columns.
#[inline(always)]
fn row<T: Real>(r: &T::M3, i: usize, v: &T::V3) -> T {
    r.col(0).get(i) * v.get(0) + r.col(1).get(i) * v.get(1) + r.col(2).get(i) * v.get(2)
}

/// Component `C` (`[linear; angular]` order) of `x.act_force(f)`, with the same operations in
/// the same order, so it equals that component of the whole product bit for bit at a third of
/// its cost.
#[inline(always)]
fn axis_component<T: Real, const C: u8>(x: &Se3<T>, f: &Force<T>) -> T {
    let r = &x.rotation;
    if C < 3 {
        return row::<T>(r, usize::from(C), &f.linear);
    }
    let t = &x.translation;
    let (tx, ty, tz) = (t.get(0), t.get(1), t.get(2));
    // Component `C - 3` of `t × (R·f)`, as `DVec3::cross` computes it.
    let cross = match C - 3 {
        0 => ty * row::<T>(r, 2, &f.linear) - row::<T>(r, 1, &f.linear) * tz,
        1 => tz * row::<T>(r, 0, &f.linear) - row::<T>(r, 2, &f.linear) * tx,
        _ => tx * row::<T>(r, 1, &f.linear) - row::<T>(r, 0, &f.linear) * ty,
    };
    row::<T>(r, usize::from(C - 3), &f.angular) + cross
}

/// [`axis_component`] for a component known at run time (`c < 6`): the constant keeps the
/// entries in registers.
#[inline(always)]
fn axis_component_of<T: Real>(x: &Se3<T>, f: &Force<T>, c: u8) -> T {
    match c {
        0 => axis_component::<T, 0>(x, f),
        1 => axis_component::<T, 1>(x, f),
        2 => axis_component::<T, 2>(x, f),
        3 => axis_component::<T, 3>(x, f),
        4 => axis_component::<T, 4>(x, f),
        _ => axis_component::<T, 5>(x, f),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_kinematics::model::RootJoint;

    #[test]
    fn the_axis_component_is_that_of_the_whole_force_transform_bit_for_bit() {
        let x = Se3::from_xyz_rpy([0.31, -0.27, 0.093], [0.4, -1.1, 2.3]);
        let f = Force::from_array([0.7, -1.9, 0.35, -0.21, 1.3, 0.77]);
        let whole = x.act_force(&f).to_array();
        for k in 0..3u8 {
            assert_eq!(
                axis_component_of(&x, &f, k).to_bits(),
                whole[k as usize].to_bits()
            );
            assert_eq!(
                axis_component_of(&x, &f, 3 + k).to_bits(),
                whole[3 + k as usize].to_bits()
            );
        }
    }

    #[test]
    fn finite_entries_whose_probe_overflows_are_accepted() {
        // Two prismatic branches from the base, each carrying 1.5e308 kg: the diagonal is
        // [1.5e308, 1.5e308], finite, though the sweep's probe (their sum) overflows.
        let urdf = r#"<robot name="r"><link name="a"/>
          <link name="b"><inertial><mass value="1.5e308"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <link name="c"><inertial><mass value="1.5e308"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="j1" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
          <joint name="j2" type="prismatic"><parent link="a"/><child link="c"/><axis xyz="0 1 0"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        </robot>"#;
        let model = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap();
        let mut data = DynamicsData::new(&model);
        let m = crba(&model, &mut data, &[0.5, -0.5]).unwrap();
        assert_eq!(m, &[1.5e308, 0.0, 0.0, 1.5e308]);
    }

    #[test]
    fn the_mass_matrix_check_tells_an_overflowing_sum_from_a_bad_entry() {
        let urdf = r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
          <joint name="j1" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
          <joint name="j2" type="continuous"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/></joint>
        </robot>"#;
        let model = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap();
        let mut data = DynamicsData::new(&model);
        // Finite entries whose sum overflows: accepted.
        data.mass_matrix
            .copy_from_slice(&[1.5e308, 1.5e308, 1.5e308, 1.5e308]);
        assert!(check_mass_matrix(&model, &data).is_ok());
        // A non-finite entry, wherever it is: refused, naming its joint.
        for (k, joint) in [(0, "j1"), (3, "j2")] {
            for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
                data.mass_matrix.copy_from_slice(&[1.0, 0.5, 0.5, 2.0]);
                data.mass_matrix[k] = bad;
                match check_mass_matrix(&model, &data) {
                    Err(DynamicsError::Overflow { joint: j, .. }) => assert_eq!(j, joint),
                    other => panic!("{other:?}"),
                }
            }
        }
    }
}
