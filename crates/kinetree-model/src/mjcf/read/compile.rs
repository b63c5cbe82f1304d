//! The whole document: sections, gravity, and the compile from XML to [`ModelBuilder`].

use super::*;

/// The top-level sections whose content kinetree does not model; their children are counted in
/// [`Model::ignored`].
pub(super) const UNMODELLED: [&str; 9] = [
    "actuator",
    "tendon",
    "equality",
    "sensor",
    "contact",
    "keyframe",
    "deformable",
    "extension",
    "custom",
];

/// Sections that only affect rendering or the simulator's settings.
pub(super) const PRESENTATION: [&str; 4] = ["visual", "statistic", "size", "option"];

pub(super) fn section_counts(root: &Element, ignored: &mut BTreeMap<String, usize>) -> Res<()> {
    const KNOWN: [&str; 6] = [
        "compiler",
        "default",
        "asset",
        "worldbody",
        "include",
        "plugin",
    ];
    for s in &root.children {
        let name = s.name.as_str();
        if UNMODELLED.contains(&name) {
            for c in &s.children {
                *ignored.entry(format!("{name}/{}", c.name)).or_default() += 1;
            }
        } else if !PRESENTATION.contains(&name) && !KNOWN.contains(&name) {
            return fail(s, format!("unknown element <{name}> in <mujoco>"));
        }
    }
    Ok(())
}

pub(super) fn gravity(root: &Element) -> Res<DVec3> {
    let mut g = DVec3::new(0.0, 0.0, -9.81);
    let mut enabled = true;
    for o in root.children.iter().filter(|c| c.name == "option") {
        if let Some(t) = o.attr("gravity") {
            g = DVec3::from_array(exact::<3>(o, "gravity", t)?);
        }
        for f in o.children.iter().filter(|c| c.name == "flag") {
            if let Some(t) = f.attr("gravity") {
                enabled = match t {
                    "enable" => true,
                    "disable" => false,
                    other => {
                        return fail(
                            f,
                            format!("gravity flag '{other}' is not 'enable' or 'disable'"),
                        );
                    }
                };
            }
        }
    }
    Ok(if enabled { g } else { DVec3::ZERO })
}

pub(super) fn compile(root: &Element, fallback_name: &str, model_dir: &Path) -> Res<ModelBuilder> {
    let mut compiler = Compiler::default();
    for c in root.children.iter().filter(|c| c.name == "compiler") {
        read_compiler(c, &mut compiler)?;
    }
    let mut defaults = Defaults::new();
    for d in root.children.iter().filter(|c| c.name == "default") {
        defaults.read(d, None, 0)?;
    }
    let mut ignored = BTreeMap::new();
    section_counts(root, &mut ignored)?;
    let mut reader = Reader {
        compiler,
        defaults: &defaults,
        meshes: HashMap::new(),
        model_dir: model_dir.to_path_buf(),
        ignored,
        notes: Vec::new(),
    };
    for a in root.children.iter().filter(|c| c.name == "asset") {
        reader.read_meshes(a)?;
    }
    let mut world = BodyData {
        e: root,
        world: true,
        name: Some(WORLD_BODY.to_string()),
        pose: Se3::IDENTITY,
        joints: Vec::new(),
        geoms: Vec::new(),
        sites: Vec::new(),
        inertial: None,
        children: Vec::new(),
    };
    for w in root.children.iter().filter(|c| c.name == "worldbody") {
        if let Some((k, _)) = w.attrs.first() {
            return fail(
                w,
                format!("the world body cannot have attributes (got '{k}')"),
            );
        }
        let scope = Scope {
            class: 0,
            frame: Se3::IDENTITY,
            depth: 0,
        };
        reader.read_children(w, scope, &mut world)?;
    }
    let masses = reader.masses(&world)?;
    check_moving(&world, &masses, &mut 0)?;
    let name = root.attr("model").unwrap_or(fallback_name);
    let mut b = ModelBuilder::new(name);
    b.gravity(gravity(root)?);
    b.add_link(link_of(WORLD_BODY, &world, &masses[0]));
    let mut emitter = Emitter {
        masses: &masses,
        body_id: 1,
        site_id: 0,
        notes: Vec::new(),
    };
    emitter.sites(&mut b, &world, WORLD_BODY);
    for c in &world.children {
        emitter.body(&mut b, c, WORLD_BODY, true)?;
    }
    for (what, count) in &reader.ignored {
        b.note_ignored(if *count == 1 {
            what.clone()
        } else {
            format!("{what} (×{count})")
        });
    }
    for note in reader.notes.iter().chain(&emitter.notes) {
        b.note_ignored(note.clone());
    }
    let _ = &reader.model_dir;
    Ok(b)
}

/// Reads an MJCF document; `path` is where it came from (for `<include>`, mesh folders and
/// error messages).
pub(crate) fn from_mjcf(text: &str, path: Option<&Path>) -> Result<Model, ModelError> {
    let mut files = Files {
        paths: vec![path.map(Path::to_path_buf)],
    };
    let mut root = xml_tree::parse(text, 0).map_err(|x| ModelError::Xml {
        file: path.map(Path::to_path_buf),
        line: x.line,
        column: x.column,
        message: x.message,
    })?;
    if root.name != "mujoco" {
        return Err(files.error(Located {
            file: 0,
            line: root.line,
            element: root.name.clone(),
            message: "the root element of an MJCF file is <mujoco>".to_string(),
        }));
    }
    let model_dir = path
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let fallback = path
        .and_then(Path::file_stem)
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mujoco".to_string());
    let mut included = HashSet::new();
    if let Some(p) = path {
        included.insert(p.canonicalize().unwrap_or_else(|_| p.to_path_buf()));
    }
    let result = expand_includes(&mut root, &mut files, &model_dir, &mut included, 0)
        .and_then(|()| compile(&root, &fallback, &model_dir));
    xml_tree::drop_flat(root);
    result.map_err(|l| files.error(l))?.build()
}
