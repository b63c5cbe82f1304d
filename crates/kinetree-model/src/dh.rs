//! Denavit–Hartenberg import: serial arms from standard or modified (Craig) DH tables.
//!
//! Each row of a table describes one joint and the link it moves:
//!
//! - **Standard** (distal) DH, row `i`: `ᶦ⁻¹Tᵢ = Rz(θᵢ) · Tz(dᵢ) · Tx(aᵢ) · Rx(αᵢ)`. Joint `i`
//!   turns about (revolute) or slides along (prismatic) the z axis of DH frame `i-1`.
//! - **Modified** (proximal, Craig) DH, row `i`: `ᶦ⁻¹Tᵢ = Rx(αᵢ₋₁) · Tx(aᵢ₋₁) · Rz(θᵢ) · Tz(dᵢ)`;
//!   the row holds `aᵢ₋₁` and `αᵢ₋₁` in its `a` and `alpha` fields. Joint `i` acts about the z
//!   axis of DH frame `i`.
//!
//! For a revolute row the joint variable is added to `theta` (so `theta` is the offset at
//! `q = 0`); for a prismatic row it is added to `d`.
//!
//! The model has a base link (`base`, DH frame 0) and one link per row (`link1`, `link2`, …,
//! unless named), each driven by a joint (`joint1`, …) whose axis is z. A link's frame is its
//! joint frame: with modified DH it is DH frame `i`; with standard DH it is DH frame `i-1`
//! turned by `θᵢ + q` and shifted by `dᵢ`, and DH frame `i` sits at `Tx(aᵢ) · Rx(αᵢ)` in it.
//! Every row adds a named frame `dh{i}` for DH frame `i` on link `i`, and an optional tool pose
//! adds a `tool` frame at `DH frame n · tool`.
//!
//! # Examples
//! The textbook's two-link planar arm:
//! ```
//! use kinetree_model::dh::{DhConvention, DhRow, DhTable};
//! use kinetree_model::Model;
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! let table = DhTable::new("planar", DhConvention::Standard)
//!     .with_row(DhRow::revolute(1.0, 0.0, 0.0, 0.0))
//!     .with_row(DhRow::revolute(0.8, 0.0, 0.0, 0.0));
//! let arm = Model::from_dh(&table)?;
//! assert_eq!(arm.nq(), 2);
//! assert!(arm.frame_index("dh2").is_some());
//! # Ok(())
//! # }
//! ```

use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::error::ModelError;
use crate::joint::{JointKind, JointLimits};
use crate::link::{Inertial, Link};
use crate::model::Model;
use glam::DVec3;
use kinetree_spatial::Se3;

/// Which Denavit–Hartenberg convention a table follows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DhConvention {
    /// Standard (distal) DH: `Rz(θ) · Tz(d) · Tx(a) · Rx(α)`.
    #[default]
    Standard,
    /// Modified (proximal) DH after Craig: `Rx(α) · Tx(a) · Rz(θ) · Tz(d)`, with `a` and `α` of
    /// the previous link.
    Modified,
}

/// One row of a DH table: one joint and the link it moves.
#[derive(Clone, Debug, PartialEq)]
pub struct DhRow {
    /// Link length `a` (m): along x (standard: `aᵢ`; modified: `aᵢ₋₁`).
    pub a: f64,
    /// Link twist `α` (rad): about x (standard: `αᵢ`; modified: `αᵢ₋₁`).
    pub alpha: f64,
    /// Link offset `d` (m) along z; the offset at `q = 0` for a prismatic joint.
    pub d: f64,
    /// Joint angle `θ` (rad) about z; the offset at `q = 0` for a revolute joint.
    pub theta: f64,
    /// [`JointKind::Revolute`], [`JointKind::Continuous`] or [`JointKind::Prismatic`].
    pub kind: JointKind,
    /// Joint limits (default none).
    pub limits: JointLimits,
    /// Inertial properties of the link, expressed in DH frame `i` (as DH dynamics tables give
    /// centres of mass); `None` means massless.
    pub inertial: Option<Inertial>,
    /// Joint name (default `joint{i}`, 1-based).
    pub joint_name: Option<String>,
    /// Link name (default `link{i}`, 1-based).
    pub link_name: Option<String>,
}

impl DhRow {
    /// A row of the given kind, without limits, massless, with default names.
    #[must_use]
    pub fn new(kind: JointKind, a: f64, alpha: f64, d: f64, theta: f64) -> Self {
        Self {
            a,
            alpha,
            d,
            theta,
            kind,
            limits: JointLimits::UNLIMITED,
            inertial: None,
            joint_name: None,
            link_name: None,
        }
    }

    /// A revolute row; `theta` is the angle offset at `q = 0`.
    #[must_use]
    pub fn revolute(a: f64, alpha: f64, d: f64, theta: f64) -> Self {
        Self::new(JointKind::Revolute, a, alpha, d, theta)
    }

    /// A prismatic row; `d` is the offset at `q = 0`.
    #[must_use]
    pub fn prismatic(a: f64, alpha: f64, d: f64, theta: f64) -> Self {
        Self::new(JointKind::Prismatic, a, alpha, d, theta)
    }

    /// Sets the joint limits.
    #[must_use]
    pub fn with_limits(mut self, limits: JointLimits) -> Self {
        self.limits = limits;
        self
    }

    /// Sets the link's inertial properties, expressed in DH frame `i`.
    #[must_use]
    pub fn with_inertial(mut self, inertial: Inertial) -> Self {
        self.inertial = Some(inertial);
        self
    }

    /// Names the joint and the link.
    #[must_use]
    pub fn with_names(mut self, joint: impl Into<String>, link: impl Into<String>) -> Self {
        self.joint_name = Some(joint.into());
        self.link_name = Some(link.into());
        self
    }

    /// The row's homogeneous transform `ᶦ⁻¹Tᵢ` at joint value `joint_value` (rad for a revolute
    /// row, added to `theta`; m for a prismatic one, added to `d`) in the standard (distal)
    /// convention, `Rz(θ) · Tz(d) · Tx(a) · Rx(α)`: the textbook's DH matrix.
    /// [`Se3::to_rows`] gives it as a 4x4 matrix. For a row of a modified table use
    /// [`DhRow::transform_in`].
    ///
    /// # Examples
    /// ```
    /// use kinetree_model::dh::DhRow;
    /// // a = 0.5, α = 90°: at θ = 90° the link's x axis points along the parent's y.
    /// let row = DhRow::revolute(0.5, std::f64::consts::FRAC_PI_2, 0.1, 0.0);
    /// let m = row.transform(std::f64::consts::FRAC_PI_2).to_rows();
    /// assert!((m[1][3] - 0.5).abs() < 1e-15 && (m[2][3] - 0.1).abs() < 1e-15);
    /// ```
    #[must_use]
    pub fn transform(&self, joint_value: f64) -> Se3 {
        self.transform_in(DhConvention::Standard, joint_value)
    }

    /// The row's homogeneous transform at `joint_value` in `convention`: standard
    /// `Rz(θ) · Tz(d) · Tx(a) · Rx(α)` or modified `Rx(α) · Tx(a) · Rz(θ) · Tz(d)`, with the joint
    /// value added to `theta` (revolute, continuous) or `d` (prismatic).
    #[must_use]
    pub fn transform_in(&self, convention: DhConvention, joint_value: f64) -> Se3 {
        let (theta, d) = if self.kind == JointKind::Prismatic {
            (self.theta, self.d + joint_value)
        } else {
            (self.theta + joint_value, self.d)
        };
        let rz_tz = Se3::from_rotation_z(theta) * Se3::from_translation(DVec3::Z * d);
        let tx_rx = Se3::from_translation(DVec3::X * self.a) * Se3::from_rotation_x(self.alpha);
        match convention {
            DhConvention::Standard => rz_tz * tx_rx,
            DhConvention::Modified => tx_rx * rz_tz,
        }
    }

    /// The part of the row's transform before the joint motion, and the part after it.
    fn split(&self, convention: DhConvention) -> (Se3, Se3) {
        let rz_tz = Se3::from_rotation_z(self.theta) * Se3::from_translation(DVec3::Z * self.d);
        let tx_rx = Se3::from_translation(DVec3::X * self.a) * Se3::from_rotation_x(self.alpha);
        match convention {
            DhConvention::Standard => (rz_tz, tx_rx),
            DhConvention::Modified => (tx_rx * rz_tz, Se3::IDENTITY),
        }
    }
}

/// A Denavit–Hartenberg table: a serial arm, base first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DhTable {
    /// Model name.
    pub name: String,
    /// Convention of the rows.
    pub convention: DhConvention,
    /// The rows, base to tip.
    pub rows: Vec<DhRow>,
    /// Pose of the `tool` frame in the last DH frame; `None` adds no tool frame.
    pub tool: Option<Se3>,
    /// Base link name (default `base`).
    pub base_name: Option<String>,
}

impl DhTable {
    /// An empty table.
    #[must_use]
    pub fn new(name: impl Into<String>, convention: DhConvention) -> Self {
        Self {
            name: name.into(),
            convention,
            ..Self::default()
        }
    }

    /// Appends a row.
    #[must_use]
    pub fn with_row(mut self, row: DhRow) -> Self {
        self.rows.push(row);
        self
    }

    /// The pose of DH frame `n` (the last) in DH frame 0 (the base) at joint values `q` (one per
    /// row): the product of the rows' [`DhRow::transform_in`], without the tool.
    ///
    /// # Errors
    /// [`ModelError::DhTable`] when `q` does not have one value per row.
    pub fn transform(&self, q: &[f64]) -> Result<Se3, ModelError> {
        if q.len() != self.rows.len() {
            return Err(ModelError::DhTable {
                row: q.len().min(self.rows.len()),
                message: format!(
                    "{} joint values given for {} rows",
                    q.len(),
                    self.rows.len()
                ),
            });
        }
        Ok(self.rows.iter().zip(q).fold(Se3::IDENTITY, |t, (row, &x)| {
            t * row.transform_in(self.convention, x)
        }))
    }

    /// Sets the tool pose in the last DH frame.
    #[must_use]
    pub fn with_tool(mut self, tool: Se3) -> Self {
        self.tool = Some(tool);
        self
    }
}

impl Model {
    /// Builds a serial arm from a Denavit–Hartenberg table (see the [module docs](crate::dh) for
    /// the conventions, names and frames).
    ///
    /// # Errors
    /// [`ModelError::DhTable`] naming the row when a value is not finite or the joint kind is not
    /// revolute, continuous or prismatic; [`ModelError::Invalid`] when names collide or limits are
    /// inverted.
    pub fn from_dh(table: &DhTable) -> Result<Model, ModelError> {
        dh_model(table, |_, _, _| {})
    }
}

/// The most rows a DH table may have (a serial chain of that many joints): the model of 10⁸
/// rows would not fit in memory, and no arm has more than a few dozen.
pub const MAX_DH_ROWS: usize = 10_000;

/// Builds the model of `table`; `decorate(row, link, link_from_dh)` may add to each link (for
/// example geometry given in DH frame `row + 1`) before it is added.
pub(crate) fn dh_model(
    table: &DhTable,
    decorate: impl Fn(usize, &mut Link, &Se3),
) -> Result<Model, ModelError> {
    if table.rows.len() > MAX_DH_ROWS {
        return Err(ModelError::DhTable {
            row: MAX_DH_ROWS,
            message: format!(
                "the table has {} rows, more than the {MAX_DH_ROWS} accepted",
                table.rows.len()
            ),
        });
    }
    let mut b = ModelBuilder::new(table.name.clone());
    let base = table.base_name.clone().unwrap_or_else(|| "base".into());
    b.add_link(Link::new(base.clone()));
    let mut parent = base;
    // Pose of the next joint's frame in the current link's frame, before the row's own part.
    let mut carry = Se3::IDENTITY;
    for (i, row) in table.rows.iter().enumerate() {
        let dh_error = |message: &str| ModelError::DhTable {
            row: i,
            message: message.to_string(),
        };
        if ![row.a, row.alpha, row.d, row.theta]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(dh_error("a, alpha, d and theta must be finite"));
        }
        if !matches!(
            row.kind,
            JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic
        ) {
            return Err(dh_error(&format!(
                "a DH joint is revolute, continuous or prismatic, not {}",
                row.kind
            )));
        }
        let n = i + 1;
        let link_name = row.link_name.clone().unwrap_or_else(|| format!("link{n}"));
        let joint_name = row
            .joint_name
            .clone()
            .unwrap_or_else(|| format!("joint{n}"));
        let (before, after) = row.split(table.convention);
        let mut link = Link::new(link_name.clone());
        if let Some(inertial) = row.inertial {
            link.inertial = Some(Inertial {
                origin: after * inertial.origin,
                ..inertial
            });
        }
        decorate(i, &mut link, &after);
        b.add_link(link);
        b.add_joint(
            JointSpec::new(joint_name, row.kind, parent, link_name.clone())
                .with_placement(carry * before)
                .with_axis(DVec3::Z)
                .with_limits(row.limits),
        );
        b.add_frame(FrameSpec::new(format!("dh{n}"), link_name.clone(), after));
        carry = after;
        parent = link_name;
    }
    if let Some(tool) = table.tool {
        b.add_frame(FrameSpec::new("tool", parent, carry * tool));
    }
    b.build()
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::FRAC_PI_2;
    use kinetree_spatial::Symmetric3;

    #[test]
    fn tables_longer_than_the_limit_are_refused_by_row_count() {
        let row = DhRow::new(JointKind::Revolute, 0.01, 0.0, 0.0, 0.0);
        let mut table = DhTable::new("long", DhConvention::Standard);
        table.rows = vec![row; MAX_DH_ROWS + 1];
        let e = Model::from_dh(&table).unwrap_err();
        assert!(
            matches!(&e, ModelError::DhTable { row: MAX_DH_ROWS, message } if message.contains("10001 rows")),
            "{e}"
        );
        table.rows.pop();
        assert_eq!(Model::from_dh(&table).unwrap().nq(), MAX_DH_ROWS);
    }

    /// Forward kinematics by hand over the model's bodies: world pose of every body.
    fn body_poses(model: &Model, q: &[f64]) -> Vec<Se3> {
        let mut world = vec![Se3::IDENTITY; model.nbodies()];
        for (i, b) in model.bodies().iter().enumerate().skip(1) {
            let motion = match b.kind {
                JointKind::Revolute | JointKind::Continuous => {
                    Se3::from_axis_angle(b.axis, q[b.idx_q])
                }
                JointKind::Prismatic => Se3::from_translation(b.axis * q[b.idx_q]),
                other => panic!("test FK handles 1-DoF joints only, not {other}"),
            };
            world[i] = world[b.parent] * b.placement * motion;
        }
        world
    }

    fn frame_pose(model: &Model, q: &[f64], name: &str) -> Se3 {
        let (body, body_from_frame) = model.frame_body(model.frame_index(name).unwrap());
        body_poses(model, q)[body] * body_from_frame
    }

    /// The DH product computed directly from the table's formulas.
    fn dh_product(table: &DhTable, q: &[f64]) -> Se3 {
        let mut t = Se3::IDENTITY;
        for (row, &qi) in table.rows.iter().zip(q) {
            let (theta, d) = match row.kind {
                JointKind::Prismatic => (row.theta, row.d + qi),
                _ => (row.theta + qi, row.d),
            };
            let rz = Se3::from_rotation_z(theta) * Se3::from_translation(DVec3::Z * d);
            let rx = Se3::from_translation(DVec3::X * row.a) * Se3::from_rotation_x(row.alpha);
            t = match table.convention {
                DhConvention::Standard => t * rz * rx,
                DhConvention::Modified => t * rx * rz,
            };
        }
        t * table.tool.unwrap_or(Se3::IDENTITY)
    }

    #[test]
    fn planar_2r_matches_the_closed_form() {
        let (l1, l2) = (1.0, 0.8);
        let table = DhTable::new("planar", DhConvention::Standard)
            .with_row(DhRow::revolute(l1, 0.0, 0.0, 0.0))
            .with_row(DhRow::revolute(l2, 0.0, 0.0, 0.0))
            .with_tool(Se3::IDENTITY);
        let arm = Model::from_dh(&table).unwrap();
        assert_eq!((arm.nq(), arm.nv(), arm.links().len()), (2, 2, 3));
        for q in [[0.3, 0.9], [-1.2, 2.5], [0.0, 0.0], [3.0, -0.4]] {
            let tip = frame_pose(&arm, &q, "tool");
            let (c1, s1) = (q[0].cos(), q[0].sin());
            let (c12, s12) = ((q[0] + q[1]).cos(), (q[0] + q[1]).sin());
            let expected = DVec3::new(l1 * c1 + l2 * c12, l1 * s1 + l2 * s12, 0.0);
            assert!(
                (tip.translation - expected).length() < 1e-14,
                "q = {q:?}: {} vs {expected}",
                tip.translation
            );
            // The tool's x axis points along the second link.
            assert!((tip.rotation.x_axis - DVec3::new(c12, s12, 0.0)).length() < 1e-14);
        }
        // At q = (30°, 45°) with the textbook's lengths, by hand: x = cos 30° + 0.8 cos 75°.
        let tip = frame_pose(&arm, &[30f64.to_radians(), 45f64.to_radians()], "tool");
        assert!((tip.translation.x - 1.073_080_639_866_455_4).abs() < 1e-14);
        assert!((tip.translation.y - 1.272_740_661_031_254_6).abs() < 1e-14);
    }

    fn ur5_standard() -> DhTable {
        let d = [0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823];
        let a = [0.0, -0.425, -0.39225, 0.0, 0.0, 0.0];
        let alpha = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, -FRAC_PI_2, 0.0];
        let mut t = DhTable::new("ur5", DhConvention::Standard)
            .with_tool(Se3::from_translation(DVec3::new(0.0, 0.0, 0.05)));
        for i in 0..6 {
            t = t.with_row(DhRow::revolute(a[i], alpha[i], d[i], 0.0));
        }
        t
    }

    /// The same arm in modified DH: row i carries a and α of row i-1; the last a, α go into the
    /// tool transform.
    fn ur5_modified(standard: &DhTable) -> DhTable {
        let rows = &standard.rows;
        let mut t = DhTable::new("ur5", DhConvention::Modified);
        for i in 0..rows.len() {
            let (a, alpha) = if i == 0 {
                (0.0, 0.0)
            } else {
                (rows[i - 1].a, rows[i - 1].alpha)
            };
            t = t.with_row(DhRow::revolute(a, alpha, rows[i].d, rows[i].theta));
        }
        let last = rows.last().unwrap();
        t.with_tool(
            Se3::from_translation(DVec3::X * last.a)
                * Se3::from_rotation_x(last.alpha)
                * standard.tool.unwrap(),
        )
    }

    #[test]
    fn ur5_standard_and_modified_tables_agree() {
        let std_table = ur5_standard();
        let mod_table = ur5_modified(&std_table);
        let a = Model::from_dh(&std_table).unwrap();
        let b = Model::from_dh(&mod_table).unwrap();
        assert_eq!((a.nq(), b.nq()), (6, 6));
        let qs = [
            [0.0; 6],
            [0.1, -0.5, 0.9, -1.3, 0.7, 2.0],
            [-2.0, 1.2, -0.3, 0.4, -2.9, 0.5],
            [3.0, -3.0, 2.5, -1.5, 1.0, -0.2],
        ];
        for q in &qs {
            let ta = frame_pose(&a, q, "tool");
            let tb = frame_pose(&b, q, "tool");
            let direct = dh_product(&std_table, q);
            assert!(
                ta.abs_diff_eq(&tb, 1e-13, 1e-13),
                "q = {q:?}: {ta:?} vs {tb:?}"
            );
            assert!(ta.abs_diff_eq(&direct, 1e-13, 1e-13), "q = {q:?}");
            assert!(tb.abs_diff_eq(&dh_product(&mod_table, q), 1e-13, 1e-13));
            // Every intermediate DH frame agrees too: standard dh{i} = modified frame i+1's
            // predecessor, i.e. the same physical frame.
            for i in 1..6 {
                let fa = frame_pose(&a, q, &format!("dh{i}"));
                let fb = frame_pose(&b, q, &format!("dh{}", i + 1));
                let fb = fb * Se3::from_translation(DVec3::Z * -mod_table.rows[i].d);
                let fb = fb * Se3::from_rotation_z(-q[i]);
                assert!(fa.abs_diff_eq(&fb, 1e-13, 1e-13), "frame {i}, q = {q:?}");
            }
        }
        // Zero configuration, by hand: the UR5 stretched out along -x with the tool pointing
        // down the y axis: x = a2 + a3, y = -(d4 + d6 + tool), z = d1 - d5.
        let t0 = frame_pose(&a, &[0.0; 6], "tool");
        let expected = DVec3::new(
            -0.425 - 0.39225,
            -(0.10915 + 0.0823 + 0.05),
            0.089159 - 0.09465,
        );
        assert!(
            (t0.translation - expected).length() < 1e-14,
            "{}",
            t0.translation
        );
    }

    #[test]
    fn prismatic_rows_slide_along_z() {
        // A cartesian-like arm: slide along z, then a revolute joint.
        let table = DhTable::new("sr", DhConvention::Standard)
            .with_row(
                DhRow::prismatic(0.2, 0.0, 0.1, 0.0).with_limits(JointLimits::position(0.0, 0.5)),
            )
            .with_row(DhRow::revolute(0.3, 0.0, 0.0, FRAC_PI_2))
            .with_tool(Se3::IDENTITY);
        let m = Model::from_dh(&table).unwrap();
        let q = [0.25, 0.0];
        let tip = frame_pose(&m, &q, "tool");
        // z = d + q = 0.35; the arm goes 0.2 along x, then 0.3 along y (θ offset 90°).
        assert!((tip.translation - DVec3::new(0.2, 0.3, 0.35)).length() < 1e-14);
        assert!(tip.abs_diff_eq(&dh_product(&table, &q), 1e-14, 1e-14));
        assert_eq!(m.joint(0).limits, JointLimits::position(0.0, 0.5));
        assert_eq!(m.joint(0).kind, JointKind::Prismatic);
    }

    #[test]
    fn inertials_are_given_in_the_dh_frame() {
        let com = DVec3::new(-0.2, 0.0, 0.0);
        let table = DhTable::new("one", DhConvention::Standard).with_row(
            DhRow::revolute(0.4, FRAC_PI_2, 0.0, 0.0).with_inertial(Inertial {
                origin: Se3::from_translation(com),
                mass: 2.0,
                inertia: Symmetric3::from_diagonal(DVec3::splat(0.01)),
            }),
        );
        let m = Model::from_dh(&table).unwrap();
        let i = m.link(1).inertial.unwrap();
        // DH frame 1 sits at x = 0.4 in the link frame, so the centre of mass is at x = 0.2.
        assert!((i.origin.translation - DVec3::new(0.2, 0.0, 0.0)).length() < 1e-15);
        assert_eq!(i.mass, 2.0);
    }

    #[test]
    fn bad_rows_name_the_row() {
        let t = DhTable::new("bad", DhConvention::Modified)
            .with_row(DhRow::revolute(0.1, 0.0, 0.0, 0.0))
            .with_row(DhRow::revolute(f64::NAN, 0.0, 0.0, 0.0));
        let e = Model::from_dh(&t).unwrap_err();
        assert!(matches!(e, ModelError::DhTable { row: 1, .. }), "{e}");
        assert!(e.to_string().contains("row 1"), "{e}");
        let t = DhTable::new("bad", DhConvention::Standard).with_row(DhRow::new(
            JointKind::Spherical,
            0.0,
            0.0,
            0.0,
            0.0,
        ));
        let e = Model::from_dh(&t).unwrap_err();
        assert!(e.to_string().contains("spherical"), "{e}");
    }
}
