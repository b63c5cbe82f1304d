//! The compiled tree handed to the builder: links, joints and frames per body, and MuJoCo's
//! moving-body mass check.

use super::*;

/// Smallest mass and principal moment MuJoCo accepts on a moving body (`mjMINVAL`).
pub(super) const MJ_MINVAL: f64 = 1e-15;

/// MuJoCo's check that every body with joints can move: it has mass and inertia, or one of its
/// welded (jointless) descendants reached without crossing a joint has. `next` is the body's id;
/// it is advanced past the subtree.
pub(super) fn check_moving(body: &BodyData<'_>, masses: &[BodyMass], next: &mut usize) -> Res<()> {
    pub(super) fn carries(body: &BodyData<'_>, masses: &[BodyMass], id: usize) -> bool {
        let m = &masses[id];
        if m.mass >= MJ_MINVAL && m.moments.iter().all(|x| *x >= MJ_MINVAL) {
            return true;
        }
        let mut child_id = id + 1;
        for c in &body.children {
            if c.joints.is_empty() && carries(c, masses, child_id) {
                return true;
            }
            child_id += subtree_size(c);
        }
        false
    }
    let id = *next;
    *next += 1;
    if !body.world && !body.joints.is_empty() && !carries(body, masses, id) {
        return fail(
            body.e,
            format!(
                "body '{}' has joints but no mass or inertia (mass {:e}, principal moments {:?}), which MuJoCo refuses",
                body.name.clone().unwrap_or_else(|| format!("body{id}")),
                masses[id].mass,
                masses[id].moments
            ),
        );
    }
    for c in &body.children {
        check_moving(c, masses, next)?;
    }
    Ok(())
}

pub(super) fn subtree_size(body: &BodyData<'_>) -> usize {
    1 + body.children.iter().map(subtree_size).sum::<usize>()
}

pub(super) fn link_of(name: &str, body: &BodyData<'_>, mass: &BodyMass) -> Link {
    let mut link = Link::new(name);
    if mass.mass != 0.0 || mass.moments.iter().any(|m| *m != 0.0) {
        link.inertial = Some(Inertial {
            origin: Se3::new(mass.rot, mass.pos),
            mass: mass.mass,
            inertia: Symmetric3::from_diagonal(DVec3::from_array(mass.moments)),
        });
    }
    for g in &body.geoms {
        let Some(geometry) = &g.geometry else {
            continue;
        };
        link.visuals.push(Visual {
            name: g.name.clone(),
            origin: g.pose,
            geometry: geometry.clone(),
            material: None,
            color: g.rgba,
        });
        if g.collides {
            link.collisions.push(Collision {
                name: g.name.clone(),
                origin: g.pose,
                geometry: geometry.clone(),
            });
        }
    }
    link
}

impl Emitter<'_> {
    pub(super) fn sites(&mut self, b: &mut ModelBuilder, body: &BodyData<'_>, link: &str) {
        for s in &body.sites {
            let name = s
                .name
                .clone()
                .unwrap_or_else(|| format!("site{}", self.site_id));
            self.site_id += 1;
            b.add_frame(FrameSpec::new(name, link, s.pose));
        }
    }

    pub(super) fn body(
        &mut self,
        b: &mut ModelBuilder,
        body: &BodyData<'_>,
        parent: &str,
        parent_is_world: bool,
    ) -> Res<()> {
        let id = self.body_id;
        self.body_id += 1;
        let name = body.name.clone().unwrap_or_else(|| format!("body{id}"));
        b.add_link(link_of(&name, body, &self.masses[id]));
        let n = body.joints.len();
        let mut placement = body.pose;
        let mut prev = parent.to_string();
        if n == 0 {
            b.add_joint(
                JointSpec::new(format!("{name}:fixed"), JointKind::Fixed, &prev, &name)
                    .with_placement(placement),
            );
        }
        let free = body.joints.iter().any(|j| j.kind == MjJoint::Free);
        if free && (n > 1 || !parent_is_world) {
            return fail(
                body.e,
                "a free joint must be the only joint of a body whose parent is the world",
            );
        }
        let mut anchor = DVec3::ZERO;
        for (k, j) in body.joints.iter().enumerate() {
            let jname = j.name.clone().unwrap_or_else(|| format!("{name}:{k}"));
            let last = k + 1 == n;
            let child = if last && j.pos == DVec3::ZERO {
                name.clone()
            } else {
                let inner = format!("{name}:{k}");
                b.add_link(Link::new(&inner));
                inner
            };
            let (kind, limits) = match j.kind {
                MjJoint::Free => {
                    placement = Se3::IDENTITY;
                    (JointKind::Floating, JointLimits::UNLIMITED)
                }
                MjJoint::Ball => {
                    placement *= Se3::from_translation(j.pos);
                    if j.range.is_some() {
                        self.notes
                            .push(format!("joint '{jname}': ball joint cone limit (range)"));
                    }
                    (JointKind::Spherical, JointLimits::UNLIMITED)
                }
                MjJoint::Hinge => {
                    placement = placement
                        * Se3::from_translation(j.pos)
                        * Se3::from_axis_angle(j.axis, -j.reference);
                    match j.range {
                        Some([lo, hi]) => (JointKind::Revolute, JointLimits::position(lo, hi)),
                        None => (JointKind::Continuous, JointLimits::UNLIMITED),
                    }
                }
                MjJoint::Slide => {
                    placement = placement
                        * Se3::from_translation(j.pos)
                        * Se3::from_translation(-j.axis * j.reference);
                    match j.range {
                        Some([lo, hi]) => (JointKind::Prismatic, JointLimits::position(lo, hi)),
                        None => (JointKind::Prismatic, JointLimits::UNLIMITED),
                    }
                }
            };
            if j.stiffness != 0.0 {
                self.notes.push(format!(
                    "joint '{jname}': stiffness {} (springs are not modelled)",
                    j.stiffness
                ));
            }
            b.add_joint(
                JointSpec::new(jname, kind, &prev, &child)
                    .with_placement(placement)
                    .with_axis(j.axis)
                    .with_limits(limits)
                    .with_dynamics(j.dynamics),
            );
            prev = child;
            anchor = if j.kind == MjJoint::Free {
                DVec3::ZERO
            } else {
                j.pos
            };
            placement = Se3::from_translation(-anchor);
        }
        if n > 0 && anchor != DVec3::ZERO {
            b.add_joint(
                JointSpec::new(format!("{name}:anchor"), JointKind::Fixed, &prev, &name)
                    .with_placement(placement),
            );
        }
        self.sites(b, body, &name);
        for c in &body.children {
            self.body(b, c, &name, false)?;
        }
        Ok(())
    }
}
