//! Batched CRBA: the block loop over `L` states at a time around the one-state sweeps of
//! `crba.rs` (`place`, `sweep`) instantiated on lanes. What is here is the edge: the block's
//! configurations into lanes, and the entries the sweep computes out to each state's matrix.

use crate::crba::{Entries, Tree, place, sweep};
use crate::data::DynamicsData;
use kinetree_kinematics::batch::{Io, block_states};
use kinetree_kinematics::joint::JointRot;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::OriginInertia;
use kinetree_kinematics::spatial::lanes::{LSe3, LaneVec, Lanes};

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
    /// The block's configurations in lanes (`Io::load_coordinates`; `nq` rounded up to 8).
    q: Vec<Lanes<L>>,
    parent_from_body: LaneVec<LSe3<L>>,
    /// The joint's rotation about its coordinate axis (revolute joints about x, y or z).
    joint_rot: LaneVec<JointRot<Lanes<L>>>,
    composite: LaneVec<OriginInertia<Lanes<L>>>,
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
            q: vec![Lanes::ZERO; model.nq().next_multiple_of(8)],
            parent_from_body: LaneVec::new(LSe3::default(), nb),
            joint_rot: LaneVec::new(JointRot::none(), nb),
            composite: LaneVec::new(OriginInertia::default(), nb),
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

/// The mass-matrix entries of CRBA's sweep in the order `crba::sweep` computes them, as the
/// places `(r·nv + c, c·nv + r)` of entry `(r, c)`, and the index of each diagonal entry among
/// them.
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

/// Where the sweep's entries go: to `entries` in the order it computes them (see
/// [`entry_layout`]), or, for a model whose block of matrices is assembled whole (`dense` not
/// empty), straight to their two places in `dense`.
struct Sink<'a, const L: usize> {
    entries: &'a mut [Lanes<L>],
    diagonal: &'a [usize],
    dense: &'a mut [Lanes<L>],
    nv: usize,
    /// The next entry's index in `entries`.
    w: usize,
}

impl<const L: usize> Entries<Lanes<L>> for Sink<'_, L> {
    #[inline(always)]
    fn put(&mut self, r: usize, c: usize, x: Lanes<L>) {
        if self.dense.is_empty() {
            self.entries[self.w] = x;
            self.w += 1;
        } else {
            self.dense[r * self.nv + c] = x;
            self.dense[c * self.nv + r] = x;
        }
    }

    #[inline(always)]
    fn add_diagonal(&mut self, k: usize, x: f64) -> Lanes<L> {
        let d = if self.dense.is_empty() {
            &mut self.entries[self.diagonal[k]]
        } else {
            &mut self.dense[k * self.nv + k]
        };
        *d += Lanes::splat(x);
        *d
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
/// caller), as `crba::compute`: the same generic sweeps on lanes.
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
    let tree = Tree::of(model, data);
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        io.load_coordinates(q, nq, &idx, &mut bufs.q);
        place(
            &tree,
            &bufs.q,
            &mut bufs.parent_from_body,
            &mut bufs.joint_rot,
        );
        let mut sink = Sink {
            entries: &mut bufs.entries,
            diagonal: &bufs.diagonal,
            dense: &mut bufs.dense,
            nv,
            w: 0,
        };
        let probe = sweep(
            &tree,
            &bufs.parent_from_body,
            &bufs.joint_rot,
            &mut bufs.composite,
            &mut sink,
        );
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
