//! Composite joints in a model file: `"type": "composite"` with its `factors`, read into a
//! [`CompositeJointSpec`] and written back from the model's [`CompositeJoint`]s.

use super::schema::{FactorDoc, JointDoc, KindDoc, LimitsDoc, PositionDoc};
use crate::composite::{CompositeJointSpec, Factor};
use crate::joint::JointLimits;
use crate::model::Model;
use crate::units::Units;
use glam::DQuat;
use kinetree_spatial::Se3;

/// The composite joint `jd` (of `"type": "composite"`) placed at `placement` (SI), or a message
/// naming the joint and what is wrong.
pub(super) fn spec_from_doc(
    jd: &JointDoc,
    placement: Se3,
    units: Units,
) -> Result<CompositeJointSpec, String> {
    let name = &jd.name;
    let not_here = [
        ("axis", jd.axis.is_some()),
        ("limits", jd.limits.is_some()),
        ("dynamics", jd.dynamics.is_some()),
        ("mimic", jd.mimic.is_some()),
    ];
    if let Some((field, _)) = not_here.iter().find(|(_, given)| *given) {
        return Err(format!(
            "joint '{name}': a composite joint has no `{field}` (give each state variable's \
             `limits` in its factor)"
        ));
    }
    let Some(docs) = &jd.factors else {
        return Err(format!(
            "joint '{name}': a composite joint needs `factors` (e.g. [{{\"param\": \"rz\"}}])"
        ));
    };
    let mut factors = Vec::with_capacity(docs.len());
    let mut limits = Vec::new();
    for (k, f) in docs.iter().enumerate() {
        let at = |what: String| format!("joint '{name}', factor {k} ('{}'): {what}", f.param);
        let length = f.param.starts_with('t');
        let si = |x: f64| {
            if length {
                units.length.to_si(x)
            } else {
                units.angle.to_si(x)
            }
        };
        let factor = match (&f.param[..], &f.value) {
            ("quat", Some(PositionDoc::Vector(v))) => match v[..] {
                [x, y, z, w] => Factor::Rotation(DQuat::from_xyzw(x, y, z, w)),
                _ => {
                    return Err(at(format!(
                        "a quaternion value is [x, y, z, w], found {} numbers",
                        v.len()
                    )));
                }
            },
            ("quat", Some(PositionDoc::Scalar(_))) => {
                return Err(at("a quaternion value is [x, y, z, w]".into()));
            }
            (p, Some(PositionDoc::Scalar(x))) => {
                Factor::from_param(p, Some(si(*x))).ok_or_else(|| at(unknown_param()))?
            }
            (_, Some(PositionDoc::Vector(_))) => {
                return Err(at(
                    "the value of a translation or rotation is a number".into()
                ));
            }
            (p, None) => Factor::from_param(p, None).ok_or_else(|| at(unknown_param()))?,
        };
        match (&f.limits, factor) {
            (Some(_), f) if !f.is_variable() || f == Factor::Ball => {
                return Err(at(
                    "only a translation or rotation state variable has `limits`".into(),
                ));
            }
            (l, f) if f.is_variable() && f != Factor::Ball => {
                let l = l.as_ref();
                let lim = |x: Option<f64>, default: f64| x.map_or(default, si);
                limits.push(JointLimits {
                    lower: lim(l.and_then(|l| l.lower), f64::NEG_INFINITY),
                    upper: lim(l.and_then(|l| l.upper), f64::INFINITY),
                    velocity: lim(l.and_then(|l| l.velocity), f64::INFINITY),
                    effort: l.and_then(|l| l.effort).unwrap_or(f64::INFINITY),
                });
            }
            _ => {}
        }
        factors.push(factor);
    }
    // Trailing unlimited entries say nothing; keep the spec as short as the code's default.
    while limits.last() == Some(&JointLimits::UNLIMITED) {
        limits.pop();
    }
    let mut spec =
        CompositeJointSpec::new(name.clone(), jd.parent.clone(), jd.child.clone(), factors)
            .with_placement(placement)
            .with_limits(limits);
    spec.parent_frame = jd.parent_frame.clone();
    Ok(spec)
}

fn unknown_param() -> String {
    "unknown parameter; a factor's `param` is tx, ty, tz, rx, ry, rz or quat".into()
}

/// The file form of composite joint `c` of `model`: its factors and their limits in `u`, its
/// `position` from `positions` (the model's `q`, SI) when given.
pub(super) fn doc_from_composite(
    model: &Model,
    c: usize,
    (parent, parent_frame, origin): (String, Option<String>, Option<super::schema::OriginDoc>),
    positions: Option<&[f64]>,
    u: Units,
) -> JointDoc {
    let spec = &model.composites()[c].spec;
    let mut limits = spec.limits.iter();
    let finite = |x: f64| x.is_finite().then_some(x);
    let factors = spec
        .factors
        .iter()
        .map(|f| {
            let length = matches!(f, Factor::Translate(..));
            let out = |x: f64| {
                if length {
                    u.length.si_to_unit(x)
                } else {
                    u.angle.si_to_unit(x)
                }
            };
            let value = match *f {
                Factor::Translate(_, Some(x)) | Factor::Rotate(_, Some(x)) => {
                    Some(PositionDoc::Scalar(out(x)))
                }
                Factor::Rotation(r) => Some(PositionDoc::Vector(r.to_array().to_vec())),
                _ => None,
            };
            let limits = (f.is_variable() && *f != Factor::Ball)
                .then(|| limits.next())
                .flatten()
                .filter(|l| **l != JointLimits::UNLIMITED)
                .map(|l| LimitsDoc {
                    lower: finite(out(l.lower)),
                    upper: finite(out(l.upper)),
                    velocity: finite(out(l.velocity)),
                    effort: finite(l.effort),
                });
            FactorDoc {
                param: f.param(),
                value,
                limits,
            }
        })
        .collect();
    let user = model
        .user_joint_index(&spec.name)
        .unwrap_or_else(|| model.user_joint_of(model.composites()[c].joints.start));
    let position = positions
        .map(|q| {
            let coords = model.user_joint_q_coordinates(user);
            let block = &q[model.user_joint_q_range(user)];
            block
                .iter()
                .zip(coords)
                .map(|(&x, c)| c.from_si(x, u))
                .collect::<Vec<f64>>()
        })
        .filter(|v| !v.is_empty())
        .map(|v| match v[..] {
            [x] => PositionDoc::Scalar(x),
            _ => PositionDoc::Vector(v),
        });
    JointDoc {
        name: spec.name.clone(),
        kind: KindDoc::Composite,
        parent,
        child: spec.child.clone(),
        parent_frame,
        origin,
        axis: None,
        limits: None,
        dynamics: None,
        mimic: None,
        position,
        factors: Some(factors),
    }
}
