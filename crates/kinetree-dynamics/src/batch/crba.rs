//! The lane kernel of batched CRBA: the composite-inertia sweep of `crba.rs` over a block of `L`
//! states at a time, with the one-state arithmetic in the same order, so every lane is the
//! one-state result bit for bit.

use super::composite::{LOrigin, LRotation};
use crate::data::{AncestorStep, DynamicsData};
use kinetree_kinematics::batch::{Io, block_states, body_transform, revolute_axis_transform};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::RotationForm;
use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, LVec3, LaneVec, Lanes};
use kinetree_kinematics::spatial::real::Vector3 as _;

/// The largest `nv²` whose block of matrices is assembled in lanes and written through the
/// transposes (nv ≤ 64: at most 256 KiB of 8-lane buffer per workspace); larger models write
/// each state's matrix from the list of entries. Once the sweep wrote its entries straight into
/// the block (rather than into a list copied there afterwards), the block won at every size
/// measured (`kinetree bench --batch 1024`, AVX-512, one thread, min of 3 rounds, ns/state,
/// state-by-state writes → block): solo12 (nv 18, 20 KiB) 355 → 319, talos_reduced (nv 38,
/// 90 KiB) 1394 → 1304, talos_full_v2 (nv 50, 160 KiB) 2198 → 2010.
const DENSE_MAX: usize = 4096;

/// The per-body lane buffers of CRBA for one lane width, and the block's mass matrices.
#[derive(Clone, Debug, Default)]
pub(crate) struct CrbaLanes<const L: usize> {
    parent_from_body: LaneVec<LSe3<L>>,
    /// The joint's rotation about its coordinate axis (revolute joints about x, y or z).
    joint_rot: LaneVec<LRotation<L>>,
    composite: LaneVec<LOrigin<L>>,
    /// The entries the sweep computes (one per ancestor pair of degrees of freedom, the diagonal
    /// included), in the order it computes them: see [`entry_layout`]. Only for models without
    /// `dense`.
    entries: Vec<Lanes<L>>,
    /// Where each of `entries` goes in a row-major `nv x nv` matrix: its two mirrored places.
    places: Vec<(usize, usize)>,
    /// The index in `entries` of each diagonal entry (for the armature).
    diagonal: Vec<usize>,
    /// For `nv² ≤ DENSE_MAX`, the block's whole matrices in lanes, row-major (`nv²` rounded up
    /// to 8 for the transposes of `Io::store_coordinates`): the sweep writes each entry to its
    /// places ([`Sink`]), and the places no entry has stay 0. Empty for larger models, whose
    /// matrices are written state by state from `entries` ([`store_block`]).
    dense: Vec<Lanes<L>>,
}

impl<const L: usize> CrbaLanes<L> {
    pub(crate) fn new(model: &Model) -> Self {
        let nb = model.nbodies();
        let (places, diagonal) = entry_layout(model);
        let dense = model.nv() * model.nv() <= DENSE_MAX;
        Self {
            parent_from_body: LaneVec::new(LSe3::default(), nb),
            joint_rot: LaneVec::new(LRotation::Identity, nb),
            composite: LaneVec::new(LOrigin::default(), nb),
            entries: if dense {
                Vec::new()
            } else {
                vec![Lanes::ZERO; places.len()]
            },
            places,
            diagonal,
            dense: if dense {
                vec![Lanes::ZERO; (model.nv() * model.nv()).next_multiple_of(8)]
            } else {
                Vec::new()
            },
        }
    }
}

/// The mass-matrix entries of CRBA's sweep in the order [`crba`] computes them, as the places
/// `(r·nv + c, c·nv + r)` of entry `(r, c)`, and the index of each diagonal entry among them.
///
/// Bodies from last to first; each body's diagonal block (`(iᵥ+l, iᵥ+k)` for `l ≥ k`), then
/// each ancestor `j` from the parent up (`(jᵥ+l, iᵥ+k)`, `k` outer). Every other entry is zero:
/// a lane buffer of only these keeps the working set of a branched tree small.
fn entry_layout(model: &Model) -> (Vec<(usize, usize)>, Vec<usize>) {
    let (bodies, nv) = (model.bodies(), model.nv());
    let mut places = Vec::new();
    let mut diagonal = vec![0; nv];
    let mut put = |r: usize, c: usize, places: &mut Vec<(usize, usize)>| {
        if r == c {
            diagonal[r] = places.len();
        }
        places.push((r * nv + c, c * nv + r));
    };
    for i in (1..bodies.len()).rev() {
        let (iv, ni) = (bodies[i].idx_v, bodies[i].nv);
        for k in 0..ni {
            for l in k..ni {
                put(iv + l, iv + k, &mut places);
            }
        }
        let mut j = bodies[i].parent;
        while j != 0 {
            let (jv, nj) = (bodies[j].idx_v, bodies[j].nv);
            for k in 0..ni {
                for l in 0..nj {
                    put(jv + l, iv + k, &mut places);
                }
            }
            j = bodies[j].parent;
        }
    }
    (places, diagonal)
}

/// Component `c` of a force in `[linear; angular]` order (`c < 6`), as
/// [`JointModel::project_axis`] reads it.
#[inline(always)]
fn component<const L: usize>(f: &LForce<L>, c: u8) -> Lanes<L> {
    if c < 3 {
        f.linear.get(usize::from(c))
    } else {
        f.angular.get(usize::from(c - 3))
    }
}

/// `Sᵀ·f` of a joint about (`REV`) or along coordinate axis `K` (as
/// [`JointModel::project_axis`]).
#[inline(always)]
fn project_axis<const L: usize, const K: usize, const REV: bool>(f: &LForce<L>) -> Lanes<L> {
    if REV {
        f.angular.get(K)
    } else {
        f.linear.get(K)
    }
}

/// Component `C` (`[linear; angular]` order) of `x.act_force(f)`, without the other five (as
/// `crba::axis_component`, bit for bit).
#[inline(always)]
fn axis_component<const L: usize, const C: u8>(x: &LSe3<L>, f: &LForce<L>) -> Lanes<L> {
    let r = &x.rotation;
    let row = |i: usize, v: &LVec3<L>| {
        r.x_axis.get(i) * v.x + r.y_axis.get(i) * v.y + r.z_axis.get(i) * v.z
    };
    if C < 3 {
        return row(usize::from(C), &f.linear);
    }
    let t = &x.translation;
    let cross = match C - 3 {
        0 => t.y * row(2, &f.linear) - row(1, &f.linear) * t.z,
        1 => t.z * row(0, &f.linear) - row(2, &f.linear) * t.x,
        _ => t.x * row(1, &f.linear) - row(0, &f.linear) * t.y,
    };
    row(usize::from(C - 3), &f.angular) + cross
}

/// [`axis_component`] for a component known at run time (`c < 6`).
#[inline(always)]
fn axis_component_of<const L: usize>(x: &LSe3<L>, f: &LForce<L>, c: u8) -> Lanes<L> {
    match c {
        0 => axis_component::<L, 0>(x, f),
        1 => axis_component::<L, 1>(x, f),
        2 => axis_component::<L, 2>(x, f),
        3 => axis_component::<L, 3>(x, f),
        4 => axis_component::<L, 4>(x, f),
        _ => axis_component::<L, 5>(x, f),
    }
}

/// `I·S` of a joint about (`REV`) or along coordinate axis `K` (as
/// `JointModel::axis_momentum`), and its diagonal entry `Sᵀ·I·S`. The axis is a constant so
/// that the inertia's entries stay in registers.
#[inline(always)]
fn axis_momentum<const L: usize, const K: usize, const REV: bool>(
    y: &LOrigin<L>,
) -> (LForce<L>, Lanes<L>) {
    // e_K-free cross product of h with the unit vector e_K, as
    // `kinetree_spatial::axis::unit_cross`.
    let h = &y.h;
    let z = Lanes::ZERO;
    let cross = match K {
        0 => LVec3 {
            x: z,
            y: -h.z,
            z: h.y,
        },
        1 => LVec3 {
            x: h.z,
            y: z,
            z: -h.x,
        },
        _ => LVec3 { x: -h.y, y: h.x, z },
    };
    let f = if REV {
        let i = &y.i;
        let angular = match K {
            0 => LVec3 {
                x: i.xx,
                y: i.xy,
                z: i.xz,
            },
            1 => LVec3 {
                x: i.xy,
                y: i.yy,
                z: i.yz,
            },
            _ => LVec3 {
                x: i.xz,
                y: i.yz,
                z: i.zz,
            },
        };
        LForce {
            linear: cross,
            angular,
        }
    } else {
        let mut linear = LVec3::ZERO;
        *linear.get_mut(K) = y.m;
        LForce {
            linear,
            angular: -cross,
        }
    };
    let d = project_axis::<L, K, REV>(&f);
    (f, d)
}

/// [`axis_momentum`] for an axis known at run time.
#[inline(always)]
fn axis_momentum_of<const L: usize>(axis: (usize, bool), y: &LOrigin<L>) -> (LForce<L>, Lanes<L>) {
    match axis {
        (0, true) => axis_momentum::<L, 0, true>(y),
        (1, true) => axis_momentum::<L, 1, true>(y),
        (_, true) => axis_momentum::<L, 2, true>(y),
        (0, false) => axis_momentum::<L, 0, false>(y),
        (1, false) => axis_momentum::<L, 1, false>(y),
        (_, false) => axis_momentum::<L, 2, false>(y),
    }
}

/// Where the sweep's entries go, in the order it computes them (see [`entry_layout`]): to
/// `entries`, or, for a model whose block of matrices is assembled whole (`dense` not empty),
/// straight to their two places in `dense`. Every entry is also summed into `probe`.
struct Sink<'a, const L: usize> {
    entries: &'a mut [Lanes<L>],
    places: &'a [(usize, usize)],
    dense: &'a mut [Lanes<L>],
    /// The next entry's index.
    w: usize,
    probe: Lanes<L>,
}

impl<const L: usize> Sink<'_, L> {
    /// The next entry.
    #[inline(always)]
    fn put(&mut self, x: Lanes<L>) {
        self.probe += x;
        if self.dense.is_empty() {
            self.entries[self.w] = x;
        } else {
            let (a, b) = self.places[self.w];
            self.dense[a] = x;
            self.dense[b] = x;
        }
        self.w += 1;
    }
}

/// Writes the block's entries (`L` lanes each, at `places`) into the first `out.len() / nn`
/// states of `out` (each an `nn`-number matrix), zero everywhere else.
#[inline(always)]
fn store_block<const L: usize>(
    entries: &[Lanes<L>],
    places: &[(usize, usize)],
    out: &mut [f64],
    nn: usize,
) {
    for (l, o) in out.chunks_exact_mut(nn).enumerate() {
        o.fill(0.0);
        for (x, &(a, b)) in entries.iter().zip(places) {
            let v = x.0[l];
            o[a] = v;
            o[b] = v;
        }
    }
}

/// CRBA of the `n` configurations of `q` into `mass_matrix` (`n · nv²`; inputs checked by the
/// caller), as `crba::compute`.
///
/// Returns whether every state's probe (the sum of the entries its sweep wrote, as
/// `crba::compute`'s) is finite: then every entry is, and the caller need not read the
/// matrices again.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
pub(crate) fn crba<const L: usize>(
    bufs: &mut CrbaLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    n: usize,
    mass_matrix: &mut [f64],
) -> bool {
    let mut finite = true;
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let bodies = model.bodies();
    let joint_models = data.kinematics.joint_models();
    let steps = &data.ancestor_step[..];
    // Scratch for multi-DoF joints, each entry written before it is read (zeroed once, not per
    // block: the per-block zeroing was a `memset` of 2.7 KiB at 8 lanes).
    let mut f = [LForce::zero(); 6];
    let mut col = [Lanes::ZERO; 6];
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        for i in 1..bodies.len() {
            let b = &bodies[i];
            let jm = &joint_models[i];
            // Each arm copies its transform into place field by field: a tuple of the
            // transform and the rotation was moved through the stack with `memcpy`.
            bufs.joint_rot[i] = match jm.axis_index() {
                Some((k, true)) => {
                    let (x, s, c) = revolute_axis_transform(k, b, q, nq, &idx);
                    bufs.parent_from_body[i].assign(&x);
                    LRotation::Axis { k, s, c }
                }
                _ => {
                    let x = body_transform(jm, b, q, nq, &idx);
                    bufs.parent_from_body[i].assign(&x);
                    LRotation::Identity
                }
            };
            bufs.composite[i] = LOrigin::splat(&data.body_inertia[i]);
        }
        let mut sink = Sink {
            entries: &mut bufs.entries,
            places: &bufs.places,
            dense: &mut bufs.dense,
            w: 0,
            probe: Lanes::ZERO,
        };
        for i in (1..bodies.len()).rev() {
            let b = &bodies[i];
            let ni = b.nv;
            let ic = bufs.composite[i];
            let jm = &joint_models[i];
            let axis = jm.axis_index();
            let (f0, diagonal) = match axis {
                Some(axis) => {
                    let (f0, d) = axis_momentum_of(axis, &ic);
                    (f0, Some(d))
                }
                None => {
                    for k in 0..ni {
                        f[k] = ic.mul_motion(&LMotion::splat(&jm.subspace_column(k)));
                    }
                    for k in 0..ni {
                        jm.project_force(&f[k], &mut col);
                        for l in k..ni {
                            sink.put(col[l]);
                        }
                    }
                    (f[0], None)
                }
            };
            if ni == 1 {
                let mut fk = f0;
                if let Some(d) = diagonal {
                    sink.put(d);
                }
                let mut j = i;
                loop {
                    let step = steps[j];
                    if step.parent == 0 {
                        break;
                    }
                    if step.last {
                        // The root-most entry: one component of the moved force.
                        let x = axis_component_of(&bufs.parent_from_body[j], &fk, step.kind);
                        sink.put(x);
                        break;
                    }
                    fk = bufs.parent_from_body[j].act_force(&fk);
                    j = step.parent;
                    if step.kind < AncestorStep::FLOATING {
                        let x = component(&fk, step.kind);
                        sink.put(x);
                    } else {
                        let nj = bodies[j].nv;
                        joint_models[j].project_force(&fk, &mut col);
                        for l in 0..nj {
                            sink.put(col[l]);
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
                        *fk = bufs.parent_from_body[j].act_force(fk);
                    }
                    j = p;
                    let nj = bodies[j].nv;
                    for k in 0..ni {
                        joint_models[j].project_force(&f[k], &mut col);
                        for l in 0..nj {
                            sink.put(col[l]);
                        }
                    }
                }
            }
            if b.parent != 0 {
                // As `JointModel::inertia_to_parent`.
                let x = &bufs.parent_from_body[i];
                let general = matches!(data.placement_rot[i], RotationForm::General(_));
                let rotated = if axis.is_some() && !general {
                    ic.rotated(&bufs.joint_rot[i])
                        .rotated(&LRotation::splat(&data.placement_rot[i]))
                } else {
                    ic.rotated(&LRotation::General(x.rotation))
                };
                let moved = rotated.translated(&x.translation);
                bufs.composite[b.parent].add_assign(&moved);
            }
        }
        if data.has_joint_terms {
            for k in 0..nv {
                let d = if sink.dense.is_empty() {
                    &mut sink.entries[bufs.diagonal[k]]
                } else {
                    &mut sink.dense[k * nv + k]
                };
                *d += Lanes::splat(data.armature[k]);
                sink.probe += *d;
            }
        }
        let probe = sink.probe;
        if bufs.dense.is_empty() {
            store_block(
                &bufs.entries,
                &bufs.places,
                &mut mass_matrix[start * nn..(start + count) * nn],
                nn,
            );
        } else {
            // Every state's matrix out through the transposes (the places no entry has stay 0).
            io.store_coordinates(&bufs.dense, nn, mass_matrix, start, nn, count);
        }
        finite &= probe.0[..count].iter().all(|p| p.is_finite());
    }
    finite
}
