//! Reading a `<model>` (and `<world>`): links, joints, frames, geometry and includes into the
//! reader's tables.

use super::*;

impl<'a> Reader<'a> {
    pub(super) fn version(&self, e: &Element) -> Version {
        self.files.version(e.file)
    }

    pub(super) fn ignore(&mut self, what: impl Into<String>) {
        *self.ignored.entry(what.into()).or_default() += 1;
    }

    /// The `<pose>` child of `e`, if any.
    pub(super) fn pose_of(&self, e: &'a Element) -> Res<(Se3, Option<String>)> {
        let poses: Vec<&Element> = e.children.iter().filter(|c| c.name == "pose").collect();
        match poses.as_slice() {
            [] => Ok((Se3::IDENTITY, None)),
            [p] => read_pose(p, self.version(p)),
            [_, second, ..] => fail(second, format!("<{}> has more than one <pose>", e.name)),
        }
    }

    pub(super) fn name_of(&self, e: &'a Element) -> Res<String> {
        match e.attr("name").map(str::trim) {
            Some(n) if !n.is_empty() => {
                if n == "world" || n.starts_with("__") && n.ends_with("__") {
                    return fail(e, format!("the name '{n}' is reserved"));
                }
                Ok(n.to_string())
            }
            _ => fail(e, format!("<{}> needs a name attribute", e.name)),
        }
    }

    /// Reads `<model>` `e` declared in `scope`, with `prefix` before its items' names.
    pub(super) fn read_model(
        &mut self,
        e: &'a Element,
        scope: usize,
        prefix: String,
        parent_static: bool,
        depth: usize,
    ) -> Res<()> {
        if depth > MAX_XML_DEPTH {
            return fail(
                e,
                format!("models nested deeper than {MAX_XML_DEPTH} levels"),
            );
        }
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let is_static = match child(e, "static") {
            Some(s) => parse_bool(s)? || parent_static,
            None => parent_static,
        };
        let node = self.graph.add_node(Node {
            kind: Kind::Model,
            scope,
            name: name.clone(),
            e,
            pose,
            relative_to,
            attached_to: None,
            parent: usize::MAX,
            inner: None,
        })?;
        let inner = self.graph.add_scope(Scope {
            e,
            node,
            prefix: prefix.clone(),
            names: HashMap::new(),
            links: Vec::new(),
            models: Vec::new(),
            is_static,
            canonical: e.attr("canonical_link").map(str::to_string),
            placement_frame: e.attr("placement_frame").map(str::to_string),
        });
        self.graph.nodes[node].inner = Some(inner);
        self.graph.scopes[scope].models.push(inner);
        for c in &e.children {
            match c.name.as_str() {
                "link" => self.read_link(c, inner)?,
                "joint" => self.read_joint(c, inner)?,
                "frame" => self.read_frame(c, inner)?,
                "model" => {
                    let nested = format!("{prefix}{}::", self.name_of(c)?);
                    self.read_model(c, inner, nested, is_static, depth + 1)?;
                }
                "pose" | "static" => {}
                other if MODEL_IGNORED.contains(&other) => self.ignore(format!("model/{other}")),
                other => self.ignore(format!("model/{other} (unknown element)")),
            }
        }
        Ok(())
    }

    pub(super) fn read_frame(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        self.graph.add_node(Node {
            kind: Kind::Frame,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: e
                .attr("attached_to")
                .filter(|s| !s.is_empty())
                .map(str::to_string),
            parent: usize::MAX,
            inner: None,
        })?;
        Ok(())
    }

    pub(super) fn read_link(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let node = self.graph.add_node(Node {
            kind: Kind::Link,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: None,
            parent: usize::MAX,
            inner: None,
        })?;
        self.graph.scopes[scope].links.push(node);
        let mut link = LinkData {
            node,
            inertial: None,
            visuals: Vec::new(),
            collisions: Vec::new(),
        };
        for c in &e.children {
            match c.name.as_str() {
                "pose" => {}
                "inertial" => {
                    if link.inertial.is_some() {
                        return fail(c, "a link has at most one <inertial>");
                    }
                    let (inertial, relative_to) = self.read_inertial(c)?;
                    link.inertial = Some((inertial, relative_to, c));
                }
                "visual" => {
                    let s = self.read_shape(c)?;
                    link.visuals.push(s);
                }
                "collision" => {
                    let s = self.read_shape(c)?;
                    link.collisions.push(s);
                }
                other if LINK_IGNORED.contains(&other) => self.ignore(format!("link/{other}")),
                other => self.ignore(format!("link/{other} (unknown element)")),
            }
        }
        self.links.push(link);
        Ok(())
    }

    pub(super) fn read_inertial(&mut self, e: &'a Element) -> Res<(Inertial, Option<String>)> {
        let mut mass = 1.0;
        let mut inertia = Symmetric3::from_diagonal(DVec3::ONE);
        let mut origin = Se3::IDENTITY;
        let mut relative_to = None;
        for c in &e.children {
            match c.name.as_str() {
                "mass" => {
                    mass = exact::<1>(c)?[0];
                    if mass < 0.0 {
                        return fail(c, format!("negative mass {mass}"));
                    }
                    not_absurd(c, "mass", &[mass])?;
                }
                "pose" => (origin, relative_to) = read_pose(c, self.version(c))?,
                "inertia" => {
                    let mut m = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
                    for (k, key) in ["ixx", "iyy", "izz", "ixy", "ixz", "iyz"]
                        .iter()
                        .enumerate()
                    {
                        m[k] = number(c, key, m[k])?;
                    }
                    if let Some(u) = c.children.iter().find(|u| {
                        !["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].contains(&u.name.as_str())
                    }) {
                        return fail(u, format!("unknown element <{}> in <inertia>", u.name));
                    }
                    not_absurd(c, "inertia", &m)?;
                    let [xx, yy, zz, xy, xz, yz] = m;
                    inertia = Symmetric3::new(xx, xy, xz, yy, yz, zz);
                }
                "fluid_added_mass" => self.ignore("inertial/fluid_added_mass"),
                other => return fail(c, format!("unknown element <{other}> in <inertial>")),
            }
        }
        Ok((
            Inertial {
                origin,
                mass,
                inertia,
            },
            relative_to,
        ))
    }

    pub(super) fn read_shape(&mut self, e: &'a Element) -> Res<Shape<'a>> {
        let (pose, relative_to) = self.pose_of(e)?;
        let mut geometry = None;
        for c in &e.children {
            match c.name.as_str() {
                "pose" => {}
                "geometry" => geometry = self.read_geometry(c)?,
                "material" => self.ignore(format!("{}/material", e.name)),
                "surface" | "laser_retro" | "max_contacts" | "transparency" | "cast_shadows"
                | "meta" | "visibility_flags" | "plugin" => {}
                other => self.ignore(format!("{}/{other} (unknown element)", e.name)),
            }
        }
        Ok(Shape {
            e,
            name: e.attr("name").map(str::to_string),
            pose,
            relative_to,
            geometry,
        })
    }

    pub(super) fn positive(&self, e: &'a Element, name: &str) -> Res<f64> {
        let Some(c) = child(e, name) else {
            return fail(e, format!("<{}> needs <{name}>", e.name));
        };
        let x = exact::<1>(c)?[0];
        if x <= 0.0 {
            return fail(c, format!("<{name}> must be positive, got {x}"));
        }
        not_absurd(c, name, &[x])?;
        Ok(x)
    }

    pub(super) fn read_geometry(&mut self, g: &'a Element) -> Res<Option<Geometry>> {
        let Some(s) = g.children.first() else {
            return Ok(None);
        };
        let shape = match s.name.as_str() {
            "box" => {
                let Some(size) = child(s, "size") else {
                    return fail(s, "<box> needs <size>");
                };
                let size = exact::<3>(size)?;
                if size.iter().any(|x| *x <= 0.0) {
                    return fail(s, format!("box sizes must be positive, got {size:?}"));
                }
                not_absurd(s, "box size", &size)?;
                Some(Geometry::Box { size })
            }
            "sphere" => Some(Geometry::Sphere {
                radius: self.positive(s, "radius")?,
            }),
            "cylinder" => Some(Geometry::Cylinder {
                radius: self.positive(s, "radius")?,
                length: self.positive(s, "length")?,
            }),
            "capsule" => Some(Geometry::Capsule {
                radius: self.positive(s, "radius")?,
                length: self.positive(s, "length")?,
            }),
            "ellipsoid" => {
                let Some(radii) = child(s, "radii") else {
                    return fail(s, "<ellipsoid> needs <radii>");
                };
                let r = exact::<3>(radii)?;
                if r.iter().any(|x| *x <= 0.0) {
                    return fail(radii, format!("radii must be positive, got {r:?}"));
                }
                self.ignore("geometry/ellipsoid (no collision shape yet)");
                None
            }
            "mesh" => Some(self.read_mesh(s)?),
            "plane" | "heightmap" | "image" | "polyline" | "empty" | "cone" => {
                self.ignore(format!("geometry/{}", s.name));
                None
            }
            other => return fail(s, format!("unknown geometry <{other}>")),
        };
        Ok(shape)
    }

    pub(super) fn read_mesh(&mut self, m: &'a Element) -> Res<Geometry> {
        let Some(uri) = child(m, "uri") else {
            return fail(m, "<mesh> needs <uri>");
        };
        let text = uri.text.trim();
        if text.is_empty() {
            return fail(uri, "empty mesh URI");
        }
        let scale = match child(m, "scale") {
            Some(s) => {
                let v = exact::<3>(s)?;
                if v.contains(&0.0) {
                    return fail(s, format!("a mesh scale cannot be zero, got {v:?}"));
                }
                not_absurd(s, "scale", &v)?;
                v
            }
            None => [1.0; 3],
        };
        if child(m, "submesh").is_some() {
            self.ignore("mesh/submesh (the whole mesh is used)");
        }
        let filename = match self.files.resolve(text, uri.file, self.options) {
            Resolved::Found(p) => p.to_string_lossy().into_owned(),
            Resolved::Missing(p) => {
                return fail(
                    uri,
                    format!("mesh file '{text}' not found (looked for {})", p.display()),
                );
            }
            Resolved::Unresolved => {
                self.notes.push(format!(
                    "mesh '{text}' not found in the model search path (kept as written)"
                ));
                text.to_string()
            }
        };
        Ok(Geometry::Mesh { filename, scale })
    }

    pub(super) fn read_axis(&mut self, a: &'a Element) -> Res<AxisData<'a>> {
        let mut axis = AxisData {
            e: a,
            xyz: DVec3::Z,
            expressed_in: None,
            model_frame: self.version(a) < (1, 5),
            limits: JointLimits::UNLIMITED,
            dynamics: JointDynamics::default(),
            mimic: None,
        };
        let (mut lower, mut upper) = (-UNBOUNDED, UNBOUNDED);
        for c in &a.children {
            match c.name.as_str() {
                "xyz" => {
                    let xyz = DVec3::from_array(exact::<3>(c)?);
                    let n = xyz.length();
                    if n < 1e-12 {
                        return fail(c, "the joint axis is zero");
                    }
                    axis.xyz = xyz / n;
                    axis.expressed_in = c
                        .attr("expressed_in")
                        .filter(|s| !s.is_empty())
                        .map(str::to_string);
                }
                "use_parent_model_frame" => axis.model_frame = parse_bool(c)?,
                "limit" => {
                    lower = number(c, "lower", lower)?;
                    upper = number(c, "upper", upper)?;
                    let effort = number(c, "effort", -1.0)?;
                    let velocity = number(c, "velocity", -1.0)?;
                    axis.limits.effort = if effort < 0.0 { f64::INFINITY } else { effort };
                    axis.limits.velocity = if velocity < 0.0 {
                        f64::INFINITY
                    } else {
                        velocity
                    };
                    if lower > upper {
                        return fail(c, format!("lower limit {lower} above upper limit {upper}"));
                    }
                }
                "dynamics" => {
                    axis.dynamics.damping = number(c, "damping", 0.0)?;
                    axis.dynamics.friction = number(c, "friction", 0.0)?;
                    if axis.dynamics.damping < 0.0 || axis.dynamics.friction < 0.0 {
                        return fail(c, "damping and friction cannot be negative");
                    }
                    let k = number(c, "spring_stiffness", 0.0)?;
                    if k != 0.0 {
                        self.notes.push(format!(
                            "joint axis spring_stiffness {k} (springs are not modelled)"
                        ));
                    }
                }
                "mimic" => {
                    let Some(leader) = c.attr("joint").filter(|j| !j.trim().is_empty()) else {
                        return fail(c, "<mimic> needs a joint attribute");
                    };
                    let multiplier = number(c, "multiplier", 1.0)?;
                    let offset = number(c, "offset", 0.0)?;
                    let reference = number(c, "reference", 0.0)?;
                    // SDFormat: q = offset + multiplier · (q_leader − reference).
                    axis.mimic = Some((
                        leader.trim().to_string(),
                        multiplier,
                        offset - multiplier * reference,
                        c,
                    ));
                }
                "initial_position" => self.ignore("axis/initial_position"),
                other => self.ignore(format!("axis/{other} (unknown element)")),
            }
        }
        axis.limits.lower = if lower <= -UNBOUNDED {
            f64::NEG_INFINITY
        } else {
            lower
        };
        axis.limits.upper = if upper >= UNBOUNDED {
            f64::INFINITY
        } else {
            upper
        };
        Ok(axis)
    }

    pub(super) fn read_joint(&mut self, e: &'a Element, scope: usize) -> Res<()> {
        let name = self.name_of(e)?;
        let (pose, relative_to) = self.pose_of(e)?;
        let kind = match e.attr("type").unwrap_or("") {
            "fixed" => SdfJoint::Fixed,
            "revolute" => SdfJoint::Revolute,
            "continuous" => SdfJoint::Continuous,
            "prismatic" => SdfJoint::Prismatic,
            "ball" => SdfJoint::Ball,
            "universal" | "revolute2" => SdfJoint::Universal,
            "screw" => {
                return fail(
                    e,
                    format!(
                        "screw joint '{name}': kinetree has no helical joint (its translation is coupled to its rotation), so it cannot be loaded exactly"
                    ),
                );
            }
            "gearbox" => {
                return fail(
                    e,
                    format!("gearbox joint '{name}': coupled joints are not supported yet"),
                );
            }
            "" => return fail(e, format!("joint '{name}' needs a type attribute")),
            other => return fail(e, format!("joint '{name}': unknown type '{other}'")),
        };
        let link_name = |which: &str| -> Res<(String, &'a Element)> {
            match child(e, which) {
                Some(c) if !c.text.trim().is_empty() => Ok((c.text.trim().to_string(), c)),
                Some(c) => fail(c, format!("empty <{which}>")),
                None => fail(e, format!("joint '{name}' needs a <{which}>")),
            }
        };
        let parent = link_name("parent")?;
        let child_link = link_name("child")?;
        let mut axes = Vec::new();
        for c in &e.children {
            match c.name.as_str() {
                "pose" | "parent" | "child" => {}
                "axis" | "axis2" => {
                    let a = self.read_axis(c)?;
                    axes.push((c.name == "axis2", a));
                }
                "physics"
                | "sensor"
                | "thread_pitch"
                | "screw_thread_pitch"
                | "gearbox_ratio"
                | "gearbox_reference_body" => self.ignore(format!("joint/{}", c.name)),
                other => self.ignore(format!("joint/{other} (unknown element)")),
            }
        }
        axes.sort_by_key(|(second, _)| *second);
        let axes: Vec<AxisData<'a>> = axes.into_iter().map(|(_, a)| a).collect();
        let needed = match kind {
            SdfJoint::Fixed | SdfJoint::Ball => 0,
            SdfJoint::Revolute | SdfJoint::Continuous | SdfJoint::Prismatic => 1,
            SdfJoint::Universal => 2,
        };
        if axes.len() < needed {
            return fail(
                e,
                format!(
                    "joint '{name}' of type {} needs {}",
                    e.attr("type").unwrap_or_default(),
                    if needed == 1 {
                        "an <axis>"
                    } else {
                        "<axis> and <axis2>"
                    }
                ),
            );
        }
        let node = self.graph.add_node(Node {
            kind: Kind::Joint,
            scope,
            name,
            e,
            pose,
            relative_to,
            attached_to: Some(child_link.0.clone()),
            parent: usize::MAX,
            inner: None,
        })?;
        self.joints.push(JointData {
            node,
            kind,
            parent,
            child: child_link,
            axes,
        });
        Ok(())
    }

    pub(super) fn read_world(&mut self, w: &'a Element) -> Res<()> {
        let models: Vec<&Element> = w.children.iter().filter(|c| c.name == "model").collect();
        for c in &w.children {
            match c.name.as_str() {
                "model" => {
                    let prefix = if models.len() > 1 {
                        format!("{}::", self.name_of(c)?)
                    } else {
                        String::new()
                    };
                    self.read_model(c, 0, prefix, false, 1)?;
                }
                "gravity" => {
                    let g = exact::<3>(c)?;
                    not_absurd(c, "gravity", &g)?;
                    self.gravity = Some(DVec3::from_array(g));
                }
                "frame" => self.read_frame(c, 0)?,
                other => self.ignore(format!("world/{other}")),
            }
        }
        Ok(())
    }
}
