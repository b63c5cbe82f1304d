//! Mesh assets, and every body's mass and inertia as MuJoCo's compiler infers them.

use super::*;

impl<'a> Reader<'a> {
    pub(super) fn read_meshes(&mut self, asset: &'a Element) -> Res<()> {
        for m in asset.children.iter().filter(|c| c.name == "mesh") {
            let v = self.view(m, "mesh", 0)?;
            let Some(file) = m.attr("file") else {
                if m.attr("vertex").is_some() {
                    self.ignore("mesh given by vertices in the file (no collision shape)");
                    continue;
                }
                return fail(m, "a mesh asset needs a 'file' attribute");
            };
            let name = match m.attr("name") {
                Some(n) => n.to_string(),
                None => Path::new(file)
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| file.to_string()),
            };
            let scale = v.array::<3>("scale", [1.0; 3])?;
            if scale.contains(&0.0) {
                return fail(m, "a mesh scale cannot be 0");
            }
            let inertia = match v.get("inertia").unwrap_or("legacy") {
                "legacy" => MeshInertia::Legacy,
                "exact" => MeshInertia::Exact,
                "shell" => MeshInertia::Shell,
                "convex" => {
                    self.ignore(
                        "mesh inertia=\"convex\" (computed as legacy, exact for convex meshes)",
                    );
                    MeshInertia::Legacy
                }
                other => return fail(m, format!("unknown mesh inertia '{other}'")),
            };
            for attr in ["refpos", "refquat"] {
                if m.attr(attr).is_some() {
                    return fail(
                        m,
                        format!("'{attr}' (deprecated in MuJoCo) is not supported"),
                    );
                }
            }
            let dir = self
                .compiler
                .meshdir
                .clone()
                .or_else(|| self.compiler.assetdir.clone());
            let file = match dir {
                Some(d) if !Path::new(file).is_absolute() => {
                    Path::new(&d).join(file).to_string_lossy().into_owned()
                }
                _ => file.to_string(),
            };
            if self
                .meshes
                .insert(
                    name.clone(),
                    MeshAsset {
                        file,
                        scale,
                        inertia,
                    },
                )
                .is_some()
            {
                return fail(m, format!("repeated mesh name '{name}'"));
            }
        }
        Ok(())
    }

    /// A mesh asset's mass properties per unit density (see [`inertia::mesh_mass`]), read from
    /// its file with MuJoCo's single-precision vertices.
    pub(super) fn mesh_mass(&self, name: &str, g: &GeomData) -> Res<inertia::MeshMass> {
        let at = |message: String| Located {
            file: g.file,
            line: g.line,
            element: "geom".to_string(),
            message,
        };
        let Some(asset) = self.meshes.get(name) else {
            return Err(at(format!("unknown mesh '{name}'")));
        };
        let path = self.model_dir.join(&asset.file);
        let mesh = crate::mesh::read_mesh(&path)
            .map_err(|e| at(format!("mesh '{name}' ({}): {e}", path.display())))?;
        let single = crate::mesh::TriangleMesh {
            vertices: mesh
                .vertices
                .iter()
                .map(|v| v.as_vec3().as_dvec3())
                .collect(),
            triangles: mesh.triangles,
        }
        .scaled(DVec3::from_array(asset.scale));
        inertia::mesh_mass(&single.vertices, &single.triangles, asset.inertia)
            .map_err(|e| at(format!("mesh '{name}': {e}")))
    }

    /// The body's inertial frame, mass and principal moments as MuJoCo compiles them (before
    /// `settotalmass`).
    pub(super) fn body_mass(&self, body: &BodyData<'a>) -> Res<BodyMass> {
        let zero = BodyMass {
            mass: 0.0,
            pos: DVec3::ZERO,
            rot: DMat3::IDENTITY,
            moments: [0.0; 3],
        };
        if body.world {
            return Ok(zero);
        }
        let explicit = body.inertial.as_ref().map(|i| BodyMass {
            mass: i.mass,
            pos: i.pos,
            rot: i.rot,
            moments: i.moments,
        });
        let c = &self.compiler;
        let infer = explicit.is_none() || c.inertia_from_geom == FromGeom::True;
        let use_geoms = c.inertia_from_geom == FromGeom::True
            || (explicit.is_none() && c.inertia_from_geom == FromGeom::Auto);
        let mut mass = if use_geoms {
            let mut geoms = Vec::new();
            for g in &body.geoms {
                if !infer || g.group < c.group_range[0] || g.group > c.group_range[1] {
                    continue;
                }
                let measure = g.solid.measure(g.spread);
                let m = match g.mass {
                    Some(0.0) => 0.0,
                    Some(m) if measure > MJ_EPS => m,
                    Some(_) => 0.0,
                    None if g.density == 0.0 => 0.0,
                    None => g.density * measure,
                };
                if m < 0.0 || g.density < 0.0 {
                    return Err(Located {
                        file: g.file,
                        line: g.line,
                        element: "geom".to_string(),
                        message: "mass or density is negative".to_string(),
                    });
                }
                match &g.mesh {
                    None => geoms.push(GeomMass {
                        mass: m,
                        pos: g.pose.translation,
                        rot: g.pose.rotation,
                        moments: g.solid.moments(m, g.spread),
                    }),
                    Some(mesh)
                        if g.mass.is_some_and(|m| m != 0.0)
                            || (g.mass.is_none() && g.density != 0.0) =>
                    {
                        let mm = self.mesh_mass(mesh, g)?;
                        let m = match g.mass {
                            Some(m) => m,
                            None => g.density * mm.measure,
                        };
                        let (eig, rot) = inertia::mesh_principal_axes(&mm.inertia);
                        geoms.push(GeomMass {
                            mass: m,
                            pos: g.pose.transform_point(mm.com),
                            rot: g.pose.rotation * rot,
                            moments: inertia::mesh_moments(eig, mm.measure, m),
                        });
                    }
                    Some(_) => {}
                }
            }
            match inertia::from_geoms(&geoms) {
                Ok(Some(total)) => total,
                Ok(None) => explicit.unwrap_or(zero),
                Err(m) => return fail(body.e, m),
            }
        } else {
            explicit.unwrap_or(zero)
        };
        mass.mass = mass.mass.max(c.boundmass);
        for m in &mut mass.moments {
            *m = m.max(c.boundinertia);
        }
        if mass.mass < 0.0 || mass.moments.iter().any(|m| *m < 0.0) {
            return fail(body.e, "mass and inertia cannot be negative");
        }
        let [a, b, cc] = mass.moments;
        // MuJoCo's check, with room for the last bits of the principal-axes decomposition.
        let slack = 1e-12 * (a + b + cc);
        if a + b + slack < cc || a + cc + slack < b || b + cc + slack < a {
            if c.balanceinertia {
                mass.moments = [(a + b + cc) / 3.0; 3];
            } else {
                return fail(
                    body.e,
                    format!(
                        "principal moments {:?} violate A + B >= C; use <compiler balanceinertia=\"true\"> to fix",
                        mass.moments
                    ),
                );
            }
        }
        Ok(mass)
    }

    /// Every body's mass properties in depth-first order (world first), `settotalmass` applied.
    pub(super) fn masses(&self, world: &BodyData<'a>) -> Res<Vec<BodyMass>> {
        let mut out = Vec::new();
        let mut stack = vec![world];
        while let Some(b) = stack.pop() {
            out.push(self.body_mass(b)?);
            stack.extend(b.children.iter().rev());
        }
        if self.compiler.settotalmass > 0.0 {
            let total: f64 = out.iter().skip(1).map(|m| m.mass).sum();
            if total > MJ_EPS {
                let scale = self.compiler.settotalmass / total;
                for m in out.iter_mut().skip(1) {
                    m.mass *= scale;
                    for x in &mut m.moments {
                        *x *= scale;
                    }
                }
            }
        }
        Ok(out)
    }
}
