//! Candidate pairs: every pair of shapes on different bodies, minus adjacent bodies, minus
//! disabled link pairs.

use crate::error::CollisionError;
use crate::model::{CollisionModel, CollisionPair, LinkPair};
use kinetree_kinematics::model::Model;

impl CollisionModel {
    /// Whether bodies `a` and `b` are joined by one joint (one is the other's parent). Fixed-joint
    /// chains are merged into bodies, so links welded to the world are adjacent to the first
    /// moving bodies, and a hand welded to the last arm link is adjacent to the fingers.
    #[must_use]
    pub fn adjacent_bodies(&self, a: usize, b: usize) -> bool {
        a != b && (self.body_parent.get(a) == Some(&b) || self.body_parent.get(b) == Some(&a))
    }

    /// Disables every shape pair between links `link_a` and `link_b` (in either order).
    ///
    /// Returns the number of shape pairs removed (0 when the links have no candidate pair, e.g.
    /// because one has no geometry or they are adjacent). A
    /// [`CollisionData`](crate::CollisionData) created before must be created again.
    ///
    /// # Errors
    /// [`CollisionError::UnknownLink`] when a name is not a link of `model`.
    pub fn disable_link_pair(
        &mut self,
        model: &Model,
        link_a: &str,
        link_b: &str,
    ) -> Result<usize, CollisionError> {
        self.disable_link_pairs(model, [(link_a, link_b)])
    }

    /// Disables several link pairs at once (see [`CollisionModel::disable_link_pair`]) and
    /// returns the number of shape pairs removed.
    ///
    /// # Errors
    /// [`CollisionError::UnknownLink`] for the first name that is not a link of `model`; nothing
    /// is changed then.
    pub fn disable_link_pairs<'n>(
        &mut self,
        model: &Model,
        pairs: impl IntoIterator<Item = (&'n str, &'n str)>,
    ) -> Result<usize, CollisionError> {
        let find = |name: &str| {
            model
                .link_index(name)
                .ok_or_else(|| CollisionError::UnknownLink {
                    name: name.to_string(),
                })
        };
        let mut disabled = self.disabled.clone();
        for (a, b) in pairs {
            let (a, b) = (find(a)?, find(b)?);
            disabled.push((a.min(b), a.max(b)));
        }
        disabled.sort_unstable();
        disabled.dedup();
        let before = self.pairs.len();
        self.disabled = disabled;
        self.rebuild_pairs();
        Ok(before.saturating_sub(self.pairs.len()))
    }

    /// Enables every link pair again (adjacent bodies stay excluded).
    pub fn enable_all_pairs(&mut self) {
        self.disabled.clear();
        self.rebuild_pairs();
    }

    /// Recomputes `pairs`, `pair_start` and `link_pairs` from the shapes, the body tree and the
    /// disabled set.
    pub(crate) fn rebuild_pairs(&mut self) {
        let n = self.shapes.len();
        let mut pairs = Vec::new();
        let mut pair_start = Vec::with_capacity(n + 1);
        // Link pair index by (link_a, link_b) in first-seen order; dense over links.
        let mut link_pair_of = std::collections::HashMap::new();
        let mut link_pairs = Vec::new();
        for a in 0..n {
            pair_start.push(pairs.len());
            let sa = &self.shapes[a];
            for b in a + 1..n {
                let sb = &self.shapes[b];
                if sa.body == sb.body || self.adjacent_bodies(sa.body, sb.body) {
                    continue;
                }
                let key = (sa.link.min(sb.link), sa.link.max(sb.link));
                if self.disabled.binary_search(&key).is_ok() {
                    continue;
                }
                let link_pair = *link_pair_of.entry(key).or_insert_with(|| {
                    link_pairs.push(LinkPair {
                        link_a: sa.link,
                        link_b: sb.link,
                    });
                    link_pairs.len() - 1
                });
                pairs.push(CollisionPair {
                    shape_a: a,
                    shape_b: b,
                    link_pair,
                });
            }
        }
        pair_start.push(pairs.len());
        self.pairs = pairs;
        self.pair_start = pair_start;
        self.link_pairs = link_pairs;
        self.plan = crate::plan::PairPlan::of(self);
    }
}
