//! `<compiler>` settings, `<default>` classes, element attributes read through their classes, and
//! orientations.

use super::*;

impl Default for Compiler {
    fn default() -> Self {
        Self {
            angle: Angle::Degree,
            eulerseq: *b"xyz",
            autolimits: true,
            inertia_from_geom: FromGeom::Auto,
            group_range: [0, 5],
            boundmass: 0.0,
            boundinertia: 0.0,
            balanceinertia: false,
            settotalmass: -1.0,
            meshdir: None,
            assetdir: None,
        }
    }
}

pub(super) fn read_compiler(c: &Element, compiler: &mut Compiler) -> Res<()> {
    for (key, value) in &c.attrs {
        match key.as_str() {
            "angle" => {
                compiler.angle = match value.as_str() {
                    "degree" => Angle::Degree,
                    "radian" => Angle::Radian,
                    other => {
                        return fail(c, format!("angle '{other}' is not 'degree' or 'radian'"));
                    }
                }
            }
            "eulerseq" => {
                let b = value.as_bytes();
                if b.len() != 3 || !b.iter().all(|x| b"xyzXYZ".contains(x)) {
                    return fail(
                        c,
                        format!("eulerseq '{value}' must be three of x, y, z, X, Y, Z"),
                    );
                }
                compiler.eulerseq = [b[0], b[1], b[2]];
            }
            "autolimits" => compiler.autolimits = parse_bool(c, key, value)?,
            "inertiafromgeom" => {
                compiler.inertia_from_geom = match parse_tristate(c, key, value)? {
                    Some(true) => FromGeom::True,
                    Some(false) => FromGeom::False,
                    None => FromGeom::Auto,
                }
            }
            "inertiagrouprange" => {
                let [a, b] = exact::<2>(c, key, value)?;
                compiler.group_range = [a as i64, b as i64];
            }
            "boundmass" => compiler.boundmass = exact::<1>(c, key, value)?[0],
            "boundinertia" => compiler.boundinertia = exact::<1>(c, key, value)?[0],
            "balanceinertia" => compiler.balanceinertia = parse_bool(c, key, value)?,
            "settotalmass" => compiler.settotalmass = exact::<1>(c, key, value)?[0],
            "meshdir" => compiler.meshdir = Some(value.clone()),
            "assetdir" => compiler.assetdir = Some(value.clone()),
            "coordinate" if value != "local" => {
                return fail(
                    c,
                    "global coordinates are no longer supported by MuJoCo (coordinate=\"local\" only)",
                );
            }
            _ => {}
        }
    }
    Ok(())
}

impl Defaults {
    pub(super) fn new() -> Self {
        Self {
            classes: vec![Class::default()],
            names: HashMap::from([("main".to_string(), 0)]),
        }
    }

    pub(super) fn read(&mut self, d: &Element, parent: Option<usize>, depth: usize) -> Res<()> {
        if depth > MAX_XML_DEPTH {
            return fail(d, "default classes nested too deeply");
        }
        let class = match parent {
            None => {
                if d.attr("class").is_some_and(|name| name != "main") {
                    return fail(d, "the top-level default class 'main' cannot be renamed");
                }
                0
            }
            Some(p) => {
                let Some(name) = d.attr("class").filter(|n| !n.is_empty()) else {
                    return fail(d, "a nested default needs a class name");
                };
                if self.names.contains_key(name) {
                    return fail(d, format!("repeated default class name '{name}'"));
                }
                self.classes.push(Class {
                    parent: Some(p),
                    attrs: HashMap::new(),
                });
                let id = self.classes.len() - 1;
                self.names.insert(name.to_string(), id);
                id
            }
        };
        for child in &d.children {
            if child.name == "default" {
                self.read(child, Some(class), depth + 1)?;
            } else {
                let entry = self.classes[class]
                    .attrs
                    .entry(child.name.clone())
                    .or_default();
                for (k, v) in &child.attrs {
                    entry.retain(|(old, _)| old != k);
                    entry.push((k.clone(), v.clone()));
                }
            }
        }
        Ok(())
    }

    pub(super) fn find(&self, e: &Element, name: &str) -> Res<usize> {
        match self.names.get(name) {
            Some(&c) => Ok(c),
            None => fail(e, format!("unknown default class '{name}'")),
        }
    }

    /// The classes from `main` down to `class`.
    pub(super) fn chain(&self, class: usize) -> Vec<usize> {
        let mut chain = vec![class];
        let mut c = class;
        while let Some(p) = self.classes[c].parent {
            chain.push(p);
            c = p;
        }
        chain.reverse();
        chain
    }
}

impl<'a> View<'a> {
    pub(super) fn get(&self, attr: &str) -> Option<&'a str> {
        if let Some(v) = self.e.attr(attr) {
            return Some(v);
        }
        for &c in self.chain.iter().rev() {
            if let Some((_, v)) = self.defaults.classes[c]
                .attrs
                .get(self.kind)
                .and_then(|list| list.iter().find(|(k, _)| k == attr))
            {
                return Some(v.as_str());
            }
        }
        None
    }

    pub(super) fn number(&self, attr: &str, default: f64) -> Res<f64> {
        match self.get(attr) {
            Some(t) => Ok(exact::<1>(self.e, attr, t)?[0]),
            None => Ok(default),
        }
    }

    pub(super) fn array<const N: usize>(&self, attr: &str, default: [f64; N]) -> Res<[f64; N]> {
        match self.get(attr) {
            Some(t) => exact::<N>(self.e, attr, t),
            None => Ok(default),
        }
    }

    /// Up to `N` numbers that replace the leading entries of the value inherited from the
    /// classes (MuJoCo's partial `size`), applied from `main` down to the element.
    pub(super) fn prefix<const N: usize>(&self, attr: &str) -> Res<[f64; N]> {
        let mut out = [0.0; N];
        let mut apply = |text: &str| -> Res<()> {
            let v = parse_numbers(self.e, attr, text)?;
            if v.len() > N {
                return fail(
                    self.e,
                    format!(
                        "attribute '{attr}' takes at most {N} numbers, got {}",
                        v.len()
                    ),
                );
            }
            out[..v.len()].copy_from_slice(&v);
            Ok(())
        };
        for &c in &self.chain {
            if let Some((_, v)) = self.defaults.classes[c]
                .attrs
                .get(self.kind)
                .and_then(|list| list.iter().find(|(k, _)| k == attr))
            {
                apply(v)?;
            }
        }
        if let Some(v) = self.e.attr(attr) {
            apply(v)?;
        }
        Ok(out)
    }

    pub(super) fn flag(&self, attr: &str, default: bool) -> Res<bool> {
        match self.get(attr) {
            Some(t) => parse_bool(self.e, attr, t),
            None => Ok(default),
        }
    }

    pub(super) fn int(&self, attr: &str, default: i64) -> Res<i64> {
        match self.get(attr) {
            Some(t) => match t.trim().parse::<i64>() {
                Ok(i) => Ok(i),
                Err(_) => fail(
                    self.e,
                    format!("attribute '{attr}': '{t}' is not an integer"),
                ),
            },
            None => Ok(default),
        }
    }
}

/// The orientation attributes of `e` (its own, else its classes'): at most one form.
pub(super) fn orientation(v: &View<'_>, c: &Compiler) -> Res<DQuat> {
    const FORMS: [&str; 5] = ["quat", "axisangle", "euler", "xyaxes", "zaxis"];
    let own: Vec<&str> = FORMS
        .iter()
        .copied()
        .filter(|f| v.e.attr(f).is_some())
        .collect();
    if own.len() > 1 {
        return fail(
            v.e,
            format!("several orientations given ({}): use one", own.join(", ")),
        );
    }
    let form = own
        .first()
        .copied()
        .or_else(|| FORMS.iter().copied().find(|f| v.get(f).is_some()));
    let Some(form) = form else {
        return Ok(DQuat::IDENTITY);
    };
    let text = v.get(form).unwrap_or_default();
    let o = match form {
        "quat" => Orientation::Quat(exact::<4>(v.e, form, text)?),
        "axisangle" => Orientation::AxisAngle(exact::<4>(v.e, form, text)?),
        "euler" => Orientation::Euler(exact::<3>(v.e, form, text)?),
        "xyaxes" => Orientation::XyAxes(exact::<6>(v.e, form, text)?),
        _ => Orientation::ZAxis(exact::<3>(v.e, form, text)?),
    };
    match o.resolve(c.angle, &c.eulerseq) {
        Ok(q) => Ok(q),
        Err(m) => fail(v.e, format!("attribute '{form}': {m}")),
    }
}
