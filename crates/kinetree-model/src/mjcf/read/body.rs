//! The body tree: bodies, frames, joints, geoms, sites and inertials read into [`BodyData`].

use super::*;

impl<'a> Reader<'a> {
    pub(super) fn view(&self, e: &'a Element, kind: &'a str, class: usize) -> Res<View<'a>> {
        let class = match e.attr("class") {
            Some(name) => self.defaults.find(e, name)?,
            None => class,
        };
        Ok(View {
            e,
            kind,
            chain: self.defaults.chain(class),
            defaults: self.defaults,
        })
    }

    pub(super) fn ignore(&mut self, what: impl Into<String>) {
        *self.ignored.entry(what.into()).or_default() += 1;
    }

    pub(super) fn childclass(&self, e: &Element, class: usize) -> Res<usize> {
        match e.attr("childclass") {
            Some(name) => self.defaults.find(e, name),
            None => Ok(class),
        }
    }

    pub(super) fn read_joint(
        &mut self,
        e: &'a Element,
        scope: Scope,
        free: bool,
    ) -> Res<JointData> {
        // `<freejoint>` takes no defaults; `<joint type="free">` does.
        let v = if free {
            View {
                e,
                kind: "freejoint",
                chain: Vec::new(),
                defaults: self.defaults,
            }
        } else {
            self.view(e, "joint", scope.class)?
        };
        let kind = if free {
            MjJoint::Free
        } else {
            match v.get("type").unwrap_or("hinge") {
                "hinge" => MjJoint::Hinge,
                "slide" => MjJoint::Slide,
                "ball" => MjJoint::Ball,
                "free" => MjJoint::Free,
                other => return fail(e, format!("unknown joint type '{other}'")),
            }
        };
        let angle = |x: f64| match kind {
            MjJoint::Hinge | MjJoint::Ball => self.compiler.angle.to_radians(x),
            _ => x,
        };
        let range = v.array::<2>("range", [0.0, 0.0])?;
        let has_range = range != [0.0, 0.0];
        let limited = match v.get("limited") {
            Some(t) => parse_tristate(e, "limited", t)?,
            None => None,
        };
        let limited = match (kind, limited) {
            (MjJoint::Free, Some(true)) => {
                return fail(e, "a free joint cannot be limited");
            }
            (MjJoint::Free, _) => false,
            (_, Some(l)) => l,
            (_, None) => {
                if !self.compiler.autolimits && has_range {
                    return fail(
                        e,
                        "'range' is given but 'limited' is not (and <compiler autolimits=\"false\">)",
                    );
                }
                has_range
            }
        };
        let range = if limited {
            if kind == MjJoint::Ball {
                if range[0] != 0.0 {
                    return fail(e, "range[0] of a ball joint must be 0");
                }
            } else if range[0] >= range[1] {
                return fail(e, "range[0] must be smaller than range[1]");
            }
            Some([angle(range[0]), angle(range[1])])
        } else {
            None
        };
        let (pos, axis) = match kind {
            MjJoint::Free => (DVec3::ZERO, DVec3::Z),
            MjJoint::Ball => (
                scope
                    .frame
                    .transform_point(DVec3::from_array(v.array("pos", [0.0; 3])?)),
                DVec3::Z,
            ),
            _ => {
                let pos = scope
                    .frame
                    .transform_point(DVec3::from_array(v.array("pos", [0.0; 3])?));
                let axis = scope
                    .frame
                    .transform_vector(DVec3::from_array(v.array("axis", [0.0, 0.0, 1.0])?));
                let n = axis.length();
                if n < MJ_EPS {
                    return fail(e, "axis too small");
                }
                (pos, axis / n)
            }
        };
        let reference = if free { 0.0 } else { v.number("ref", 0.0)? };
        let reference = if kind == MjJoint::Hinge {
            angle(reference)
        } else {
            reference
        };
        let dynamics = if free {
            JointDynamics::default()
        } else {
            JointDynamics {
                damping: v.number("damping", 0.0)?,
                friction: v.number("frictionloss", 0.0)?,
                armature: v.number("armature", 0.0)?,
            }
        };
        let stiffness = if free {
            0.0
        } else {
            v.number("stiffness", 0.0)?
        };
        Ok(JointData {
            name: e.attr("name").map(str::to_string),
            kind,
            pos,
            axis,
            range,
            reference: if matches!(kind, MjJoint::Hinge | MjJoint::Slide) {
                reference
            } else {
                0.0
            },
            dynamics,
            stiffness,
        })
    }

    pub(super) fn read_geom(&mut self, e: &'a Element, scope: Scope) -> Res<GeomData> {
        let v = self.view(e, "geom", scope.class)?;
        let type_name = v.get("type").unwrap_or("sphere").to_string();
        let mut size = v.prefix::<3>("size")?;
        let mut pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
        let fromto = match v.get("fromto") {
            Some(t) => Some(exact::<6>(e, "fromto", t)?),
            None => None,
        };
        let quat = if let Some(ft) = fromto {
            if !matches!(
                type_name.as_str(),
                "capsule" | "cylinder" | "ellipsoid" | "box"
            ) {
                return fail(e, "fromto requires a capsule, cylinder, box or ellipsoid");
            }
            if pos != DVec3::ZERO {
                return fail(e, "both pos and fromto are given");
            }
            let from = DVec3::new(ft[0], ft[1], ft[2]);
            let to = DVec3::new(ft[3], ft[4], ft[5]);
            let vec = from - to;
            let half = vec.length() / 2.0;
            if half < MJ_EPS {
                return fail(e, "fromto points are too close");
            }
            size[1] = half;
            if matches!(type_name.as_str(), "ellipsoid" | "box") {
                size[2] = size[1];
                size[1] = size[0];
            }
            pos = (from + to) / 2.0;
            z_to(vec)
        } else {
            orientation(&v, &self.compiler)?
        };
        let mesh = v.get("mesh");
        let positive = |n: usize| -> Res<()> {
            if size[..n].iter().all(|s| *s > 0.0) {
                Ok(())
            } else {
                fail(
                    e,
                    format!(
                        "a {type_name} needs {n} positive size{} (got {:?})",
                        if n > 1 { "s" } else { "" },
                        &size[..n]
                    ),
                )
            }
        };
        let (solid, geometry) = match type_name.as_str() {
            "sphere" => {
                positive(1)?;
                (
                    Solid::Sphere(size[0]),
                    Some(Geometry::Sphere { radius: size[0] }),
                )
            }
            "capsule" => {
                positive(2)?;
                (
                    Solid::Capsule(size[0], size[1]),
                    Some(Geometry::Capsule {
                        radius: size[0],
                        length: 2.0 * size[1],
                    }),
                )
            }
            "cylinder" => {
                positive(2)?;
                (
                    Solid::Cylinder(size[0], size[1]),
                    Some(Geometry::Cylinder {
                        radius: size[0],
                        length: 2.0 * size[1],
                    }),
                )
            }
            "box" => {
                positive(3)?;
                (
                    Solid::Box(size),
                    Some(Geometry::Box {
                        size: [2.0 * size[0], 2.0 * size[1], 2.0 * size[2]],
                    }),
                )
            }
            "ellipsoid" => {
                positive(3)?;
                self.ignore("geom type ellipsoid (mass kept, no collision shape yet)");
                (Solid::Ellipsoid(size), None)
            }
            "plane" => {
                self.ignore("geom type plane (no collision shape yet)");
                (Solid::Empty, None)
            }
            "hfield" => {
                self.ignore("geom type hfield");
                (Solid::Box(size), None)
            }
            "mesh" => {
                let Some(name) = mesh else {
                    return fail(e, "a mesh geom needs a 'mesh' attribute");
                };
                let Some(asset) = self.meshes.get(name) else {
                    return fail(e, format!("unknown mesh '{name}'"));
                };
                (
                    Solid::Empty,
                    Some(Geometry::Mesh {
                        filename: asset.file.clone(),
                        scale: asset.scale,
                    }),
                )
            }
            "sdf" => {
                self.ignore("geom type sdf");
                (Solid::Empty, None)
            }
            other => return fail(e, format!("unknown geom type '{other}'")),
        };
        let mass = match v.get("mass") {
            Some(t) => Some(exact::<1>(e, "mass", t)?[0]),
            None => None,
        };
        let density = v.number("density", 1000.0)?;
        let spread = if v.flag("shellinertia", false)? {
            Spread::Shell
        } else {
            Spread::Volume
        };
        let contype = v.int("contype", 1)?;
        let conaffinity = v.int("conaffinity", 1)?;
        let rgba = match v.get("rgba") {
            Some(t) => Some(exact::<4>(e, "rgba", t)?),
            None => None,
        };
        Ok(GeomData {
            name: e.attr("name").map(str::to_string),
            pose: scope.frame * pose(pos, quat),
            geometry,
            solid,
            mass,
            density,
            spread,
            group: v.int("group", 0)?,
            collides: contype != 0 || conaffinity != 0,
            rgba,
            line: e.line,
            file: e.file,
            mesh: (type_name == "mesh").then(|| mesh.unwrap_or_default().to_string()),
        })
    }

    pub(super) fn read_inertial(&self, e: &'a Element) -> Res<InertialData> {
        let v = self.view(e, "inertial", 0)?;
        let Some(pos) = e.attr("pos") else {
            return fail(e, "missing attribute 'pos'");
        };
        let pos = DVec3::from_array(exact::<3>(e, "pos", pos)?);
        let Some(mass) = e.attr("mass") else {
            return fail(e, "missing attribute 'mass'");
        };
        let mass = exact::<1>(e, "mass", mass)?[0];
        let q = orientation(&v, &self.compiler)?;
        let (rot, moments) = match (e.attr("fullinertia"), e.attr("diaginertia")) {
            (Some(_), Some(_)) => {
                return fail(e, "fullinertia and diaginertia cannot both be given");
            }
            (Some(full), None) => {
                if q != DQuat::IDENTITY {
                    return fail(
                        e,
                        "fullinertia and an inertial orientation cannot both be given",
                    );
                }
                let [xx, yy, zz, xy, xz, yz] = exact::<6>(e, "fullinertia", full)?;
                let (moments, rot) =
                    inertia::principal_axes(&Symmetric3::new(xx, xy, xz, yy, yz, zz));
                // MuJoCo's check.
                if moments.iter().any(|m| *m < MJ_EPS) {
                    return fail(e, "fullinertia must have positive eigenvalues");
                }
                (rot, moments)
            }
            (None, Some(diag)) => (DMat3::from_quat(q), exact::<3>(e, "diaginertia", diag)?),
            (None, None) => (DMat3::from_quat(q), [0.0; 3]),
        };
        Ok(InertialData {
            mass,
            pos,
            rot,
            moments,
        })
    }

    pub(super) fn read_site(&self, e: &'a Element, scope: Scope) -> Res<SiteData> {
        let v = self.view(e, "site", scope.class)?;
        let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
        let q = orientation(&v, &self.compiler)?;
        Ok(SiteData {
            name: e.attr("name").map(str::to_string),
            pose: scope.frame * pose(pos, q),
        })
    }

    /// Reads the children of a `<body>`, `<frame>` or `<worldbody>` element into `body`.
    pub(super) fn read_children(
        &mut self,
        e: &'a Element,
        scope: Scope,
        body: &mut BodyData<'a>,
    ) -> Res<()> {
        if scope.depth > MAX_XML_DEPTH {
            return fail(
                e,
                format!("bodies and frames nested deeper than {MAX_XML_DEPTH} levels"),
            );
        }
        let world = body.world;
        for c in &e.children {
            match c.name.as_str() {
                "inertial" => {
                    if world {
                        return fail(c, "the world body cannot have an inertial");
                    }
                    if body.inertial.is_some() {
                        return fail(c, "a body has at most one inertial");
                    }
                    body.inertial = Some(self.read_inertial(c)?);
                }
                "joint" | "freejoint" => {
                    if world {
                        return fail(c, "the world body cannot have joints");
                    }
                    let j = self.read_joint(c, scope, c.name == "freejoint")?;
                    body.joints.push(j);
                }
                "geom" => {
                    let g = self.read_geom(c, scope)?;
                    body.geoms.push(g);
                }
                "site" => {
                    let s = self.read_site(c, scope)?;
                    body.sites.push(s);
                }
                "frame" => {
                    let v = View {
                        e: c,
                        kind: "frame",
                        chain: Vec::new(),
                        defaults: self.defaults,
                    };
                    let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
                    let q = orientation(&v, &self.compiler)?;
                    let inner = Scope {
                        class: self.childclass(c, scope.class)?,
                        frame: scope.frame * pose(pos, q),
                        depth: scope.depth + 1,
                    };
                    self.read_children(c, inner, body)?;
                }
                "body" => {
                    let v = View {
                        e: c,
                        kind: "body",
                        chain: Vec::new(),
                        defaults: self.defaults,
                    };
                    let pos = DVec3::from_array(v.array("pos", [0.0; 3])?);
                    let q = orientation(&v, &self.compiler)?;
                    let name = c.attr("name").map(str::to_string);
                    if name.as_deref() == Some(WORLD_BODY) {
                        return fail(c, "a body cannot be called 'world'");
                    }
                    let mut child = BodyData {
                        e: c,
                        world: false,
                        name,
                        pose: scope.frame * pose(pos, q),
                        joints: Vec::new(),
                        geoms: Vec::new(),
                        sites: Vec::new(),
                        inertial: None,
                        children: Vec::new(),
                    };
                    let inner = Scope {
                        class: self.childclass(c, scope.class)?,
                        frame: Se3::IDENTITY,
                        depth: scope.depth + 1,
                    };
                    self.read_children(c, inner, &mut child)?;
                    body.children.push(child);
                }
                "camera" | "light" => self.ignore(format!("{} (visual only)", c.name)),
                "plugin" => self.ignore("body plugin"),
                "composite" | "flexcomp" | "replicate" | "attach" => {
                    return fail(
                        c,
                        format!(
                            "<{}> generates bodies and is not supported yet; expand it with MuJoCo (mj_saveLastXML) first",
                            c.name
                        ),
                    );
                }
                other => return fail(c, format!("unknown element <{other}> in a body")),
            }
        }
        Ok(())
    }
}
