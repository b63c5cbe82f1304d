//! The frame graph resolved and handed to the builder: links, joints (composites included) and
//! frames, with the names kinetree gives to what it adds.

use super::*;

/// The kinetree name of a graph node (its scope's prefix and its name).
pub(super) fn kname(graph: &Graph<'_>, node: usize) -> String {
    let n = &graph.nodes[node];
    format!("{}{}", graph.scopes[n.scope].prefix, n.name)
}

/// A name for a joint added by the loader for `link`: the link's name, unless an SDFormat joint
/// already has it.
pub(super) fn added_joint_name(
    link: &str,
    joint_names: &std::collections::HashSet<String>,
) -> String {
    if joint_names.contains(link) {
        format!("{link}:root")
    } else {
        link.to_string()
    }
}

impl<'a> Reader<'a> {
    pub(super) fn build(mut self, model_name: &str) -> Res<(ModelBuilder, Vec<(String, Se3)>)> {
        self.graph.resolve()?;
        let graph = &self.graph;
        let mut b = ModelBuilder::new(model_name);
        if let Some(g) = self.gravity {
            b.gravity(g);
        }
        // Links.
        for l in &self.links {
            let name = kname(graph, l.node);
            let mut link = Link::new(&name);
            let mut inertial = Inertial {
                origin: Se3::IDENTITY,
                mass: 1.0,
                inertia: Symmetric3::from_diagonal(DVec3::ONE),
            };
            if let Some((i, relative_to, ie)) = &l.inertial {
                inertial = *i;
                if let Some(r) = relative_to {
                    let target = graph.lookup_or_fail(graph.nodes[l.node].scope, r, ie)?;
                    inertial.origin = graph.relative(l.node, target) * inertial.origin;
                }
            }
            link.inertial = Some(inertial);
            let place = |s: &Shape<'_>| -> Res<Se3> {
                match &s.relative_to {
                    Some(r) => {
                        let target = graph.lookup_or_fail(graph.nodes[l.node].scope, r, s.e)?;
                        Ok(graph.relative(l.node, target) * s.pose)
                    }
                    None => Ok(s.pose),
                }
            };
            for s in &l.visuals {
                if let Some(g) = &s.geometry {
                    link.visuals.push(Visual {
                        name: s.name.clone(),
                        origin: place(s)?,
                        geometry: g.clone(),
                        material: None,
                        color: None,
                    });
                }
            }
            for s in &l.collisions {
                if let Some(g) = &s.geometry {
                    link.collisions.push(Collision {
                        name: s.name.clone(),
                        origin: place(s)?,
                        geometry: g.clone(),
                    });
                }
            }
            b.add_link(link);
        }
        // Joints: which link each attaches to which, checked for second parents and cycles.
        let mut parent_of: HashMap<usize, (usize, Option<usize>)> = HashMap::new();
        let mut joint_names = std::collections::HashSet::new();
        let mut resolved = Vec::new();
        for j in &self.joints {
            let node = &graph.nodes[j.node];
            if graph.scopes[node.scope].is_static {
                self.notes.push(format!(
                    "joint '{}' of a static model (its links are welded to the world)",
                    kname(graph, j.node)
                ));
                continue;
            }
            let parent = graph.joint_end(node.scope, &j.parent.0, j.parent.1, true)?;
            let child = graph.joint_end(node.scope, &j.child.0, j.child.1, false)?;
            let Some(child) = child else {
                return fail(j.child.1, "the child of a joint cannot be the world");
            };
            if parent == Some(child) {
                return fail(node.e, "a joint cannot connect a link to itself");
            }
            if let Some((other, _)) = parent_of.get(&child) {
                return fail(
                    node.e,
                    format!(
                        "link '{}' already has a parent joint, '{}': the links must form a tree",
                        kname(graph, child),
                        kname(graph, *other)
                    ),
                );
            }
            if graph.scopes[graph.nodes[child].scope].is_static {
                return fail(
                    node.e,
                    format!(
                        "the child link '{}' belongs to a static model",
                        kname(graph, child)
                    ),
                );
            }
            parent_of.insert(child, (j.node, parent));
            joint_names.insert(kname(graph, j.node));
            resolved.push((j, parent, child));
        }
        for &(_, _, start) in &resolved {
            let mut at = start;
            let mut steps = 0;
            while let Some(&(joint, Some(p))) = parent_of.get(&at) {
                steps += 1;
                if p == start || steps > parent_of.len() {
                    return fail(
                        graph.nodes[joint].e,
                        format!(
                            "joint '{}' closes a kinematic loop through link '{}'",
                            kname(graph, joint),
                            kname(graph, start)
                        ),
                    );
                }
                at = p;
            }
        }
        for (j, parent, child) in resolved {
            self.emit_joint(&mut b, j, parent, child)?;
        }
        // Roots: static links welded, free trees floating (or welded, as asked).
        let mut floating = Vec::new();
        for l in &self.links {
            if parent_of.contains_key(&l.node) {
                continue;
            }
            let graph = &self.graph;
            let name = kname(graph, l.node);
            let world_from_link = graph.relative(0, l.node);
            let jname = added_joint_name(&name, &joint_names);
            let is_static = graph.scopes[graph.nodes[l.node].scope].is_static;
            if is_static || self.options.free_trees == RootJoint::Fixed {
                b.add_joint(
                    JointSpec::new(jname, JointKind::Fixed, "world", &name)
                        .with_placement(world_from_link),
                );
            } else {
                b.add_joint(JointSpec::new(&jname, JointKind::Floating, "world", &name));
                floating.push((jname, world_from_link));
            }
        }
        // Frames.
        for (id, n) in self.graph.nodes.iter().enumerate() {
            if n.kind != Kind::Frame || n.scope == 0 {
                continue;
            }
            match self.graph.attached_link(id)? {
                Some(link) => {
                    b.add_frame(FrameSpec::new(
                        kname(&self.graph, id),
                        kname(&self.graph, link),
                        self.graph.relative(link, id),
                    ));
                }
                None => self.notes.push(format!(
                    "frame '{}' attached to the world",
                    kname(&self.graph, id)
                )),
            }
        }
        for (what, count) in &self.ignored {
            b.note_ignored(if *count == 1 {
                what.clone()
            } else {
                format!("{what} (×{count})")
            });
        }
        for note in &self.notes {
            b.note_ignored(note.clone());
        }
        Ok((b, floating))
    }

    /// The axis of `a` in the joint frame of `joint`.
    pub(super) fn axis_in_joint(&self, joint: usize, a: &AxisData<'_>) -> Res<DVec3> {
        let g = &self.graph;
        let scope = g.nodes[joint].scope;
        let frame = match &a.expressed_in {
            Some(name) => Some(g.lookup_or_fail(scope, name, a.e)?),
            None if a.model_frame => Some(g.scopes[scope].node),
            None => None,
        };
        Ok(match frame {
            Some(f) => g.relative(joint, f).rotation * a.xyz,
            None => a.xyz,
        })
    }

    pub(super) fn emit_joint(
        &self,
        b: &mut ModelBuilder,
        j: &JointData<'_>,
        parent: Option<usize>,
        child: usize,
    ) -> Res<()> {
        let g = &self.graph;
        let name = kname(g, j.node);
        let parent_name = parent.map_or_else(|| "world".to_string(), |p| kname(g, p));
        let child_name = kname(g, child);
        let parent_from_joint = g.relative(parent.unwrap_or(0), j.node);
        let joint_from_child = g.relative(j.node, child);
        let target = if joint_from_child == Se3::IDENTITY {
            child_name.clone()
        } else {
            let inner = format!("{name}:frame");
            b.add_link(Link::new(&inner));
            b.add_joint(
                JointSpec::new(
                    format!("{name}:child"),
                    JointKind::Fixed,
                    &inner,
                    &child_name,
                )
                .with_placement(joint_from_child),
            );
            inner
        };
        let first = j.axes.first();
        let (kind, limits) = match j.kind {
            SdfJoint::Fixed => (JointKind::Fixed, JointLimits::UNLIMITED),
            SdfJoint::Ball => (JointKind::Spherical, JointLimits::UNLIMITED),
            SdfJoint::Continuous => (
                JointKind::Continuous,
                first.map_or(JointLimits::UNLIMITED, |a| JointLimits {
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    ..a.limits
                }),
            ),
            SdfJoint::Revolute => {
                let l = first.map_or(JointLimits::UNLIMITED, |a| a.limits);
                if l.lower.is_infinite() && l.upper.is_infinite() {
                    (JointKind::Continuous, l)
                } else {
                    (JointKind::Revolute, l)
                }
            }
            SdfJoint::Prismatic => (
                JointKind::Prismatic,
                first.map_or(JointLimits::UNLIMITED, |a| a.limits),
            ),
            SdfJoint::Universal => {
                let a1 = self.axis_in_joint(j.node, &j.axes[0])?;
                let a2 = self.axis_in_joint(j.node, &j.axes[1])?;
                if a1.dot(a2).abs() > 1e-9 {
                    return fail(
                        g.nodes[j.node].e,
                        format!(
                            "joint '{name}': the two axes of a universal joint must be perpendicular (cos = {:e})",
                            a1.dot(a2)
                        ),
                    );
                }
                let a2 = (a2 - a1 * a1.dot(a2)).normalize();
                let r = DMat3::from_cols(a1, a2, a1.cross(a2));
                let q = DQuat::from_mat3(&r);
                let spec = CompositeJointSpec::new(
                    &name,
                    &parent_name,
                    &target,
                    [
                        Factor::Rotate(Axis::X, None),
                        Factor::Rotate(Axis::Y, None),
                        Factor::Rotation(q.conjugate()),
                    ],
                )
                .with_placement(parent_from_joint * Se3::new(r, DVec3::ZERO))
                .with_limits([j.axes[0].limits, j.axes[1].limits]);
                b.add_composite(spec);
                return Ok(());
            }
        };
        let axis = match first {
            Some(a) if kind.has_axis() => self.axis_in_joint(j.node, a)?,
            _ => DVec3::X,
        };
        let mut spec = JointSpec::new(&name, kind, &parent_name, &target)
            .with_placement(parent_from_joint)
            .with_axis(axis)
            .with_limits(
                if kind.has_position_limits() || kind == JointKind::Continuous {
                    limits
                } else {
                    JointLimits::UNLIMITED
                },
            );
        if let Some(a) = first.filter(|_| kind.is_moving()) {
            spec = spec.with_dynamics(a.dynamics);
            if let Some((leader, multiplier, offset, e)) = &a.mimic {
                let scope = g.nodes[j.node].scope;
                let n = g.lookup_or_fail(scope, leader, e)?;
                if g.nodes[n].kind != Kind::Joint {
                    return fail(e, format!("mimic joint '{leader}' is not a joint"));
                }
                spec = spec.with_mimic(kname(g, n), *multiplier, *offset);
            }
        }
        b.add_joint(spec);
        Ok(())
    }
}
