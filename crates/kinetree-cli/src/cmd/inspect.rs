//! `kinetree inspect <model>`: what a model file contains, as kinetree reads it.

use crate::table::Table;
use anyhow::Result;
use kinetree::model::{Model, RootJoint};
use kinetree::spatial::Se3;
use std::fmt::Write;
use std::path::PathBuf;

/// Arguments of `kinetree inspect`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The model file (.urdf or .json).
    model: PathBuf,
    /// Attach the root link by a 6-DoF floating joint instead of welding it to the world.
    #[arg(long)]
    floating: bool,
}

/// Loads the model and prints the report.
pub(crate) fn run(args: &Args) -> Result<()> {
    let model = super::load_model(&args.model, super::root_joint(args.floating))?;
    out!("{}", report(&model, &args.model.display().to_string()))?;
    Ok(())
}

/// The whole report: the tree, dimensions, joints, links and masses, frames, ignored elements
/// and warnings.
fn report(model: &Model, file: &str) -> String {
    let mut out = String::new();
    // The model's Display is the header `name (nq = …, nv = …)` and the indented tree.
    let _ = write!(out, "{model}");
    let joint_count = model.user_joints().len();
    let moving = model.moving_user_joints().count();
    let link_count = (0..model.links().len())
        .filter(|&l| !model.is_virtual_link(l))
        .count();
    let root = match model.root_joint() {
        RootJoint::Fixed => "fixed (welded to the world)",
        RootJoint::Floating => "floating (6-DoF root joint)",
    };
    let _ = writeln!(out);
    let _ = writeln!(out, "file:    {file}");
    let _ = writeln!(out, "root:    {root}");
    let _ = writeln!(
        out,
        "size:    nq = {}, nv = {}; {link_count} links, {joint_count} joints ({moving} moving), {} bodies (world included)",
        model.nq(),
        model.nv(),
        model.nbodies()
    );
    if !model.composites().is_empty() {
        let _ = writeln!(
            out,
            "         {} composite joint(s), built from {} elementary joints through {} massless virtual links",
            model.composites().len(),
            model
                .composites()
                .iter()
                .map(|c| c.joints.len())
                .sum::<usize>(),
            model
                .composites()
                .iter()
                .map(|c| c.links.len())
                .sum::<usize>(),
        );
    }
    let _ = writeln!(out, "gravity: {} m/s²", vec3(model.gravity().to_array()));

    let _ = writeln!(out, "\njoints ({joint_count}):");
    let mut joints = Table::new(&[
        "name",
        "type",
        "parent → child",
        "axis",
        ">lower",
        ">upper",
        ">velocity",
        ">effort",
        ">idx_q",
        ">idx_v",
    ]);
    for (u, user) in model.user_joints().iter().enumerate() {
        let j = user.joints.start;
        let joint = model.joint(j);
        if let Some(c) = user.composite {
            joints.row(composite_row(model, u, c));
            continue;
        }
        let parent = joint
            .parent_link
            .map_or("world", |p| model.link(p).name.as_str());
        let child = &model.link(joint.child_link).name;
        let axis = if joint.kind.has_axis() {
            vec3(joint.axis.to_array())
        } else {
            "-".to_string()
        };
        let (lower, upper) = if joint.kind.has_position_limits() {
            (num(joint.limits.lower), num(joint.limits.upper))
        } else {
            ("-".to_string(), "-".to_string())
        };
        let (velocity, effort) = if joint.kind.is_moving() {
            (num(joint.limits.velocity), num(joint.limits.effort))
        } else {
            ("-".to_string(), "-".to_string())
        };
        let (q, v) = (model.joint_q_range(j), model.joint_v_range(j));
        let index = |r: core::ops::Range<usize>| {
            if r.is_empty() {
                "-".to_string()
            } else {
                r.start.to_string()
            }
        };
        joints.row(vec![
            joint.name.clone(),
            joint.kind.to_string(),
            format!("{parent} → {child}"),
            axis,
            lower,
            upper,
            velocity,
            effort,
            index(q),
            index(v),
        ]);
    }
    let _ = write!(out, "{joints}");

    let _ = writeln!(out, "\nlinks ({link_count}):");
    let mut links = Table::new(&[
        "name",
        ">mass (kg)",
        "centre of mass (link frame, m)",
        ">visuals",
        ">collisions",
    ]);
    let authored = model
        .links()
        .iter()
        .enumerate()
        .filter(|&(l, _)| !model.is_virtual_link(l));
    for (_, link) in authored {
        let (mass, com) = link
            .inertial
            .map_or(("-".to_string(), "-".to_string()), |i| {
                (num(i.mass), vec3(i.origin.translation.to_array()))
            });
        links.row(vec![
            link.name.clone(),
            mass,
            com,
            link.visuals.len().to_string(),
            link.collisions.len().to_string(),
        ]);
    }
    let _ = write!(out, "{links}");
    let _ = writeln!(out, "  total mass: {} kg", num(model.total_mass()));

    let _ = writeln!(out, "\nframes ({}):", model.frames().len());
    if model.frames().is_empty() {
        let _ = writeln!(out, "  none");
    } else {
        let mut frames = Table::new(&["name", "link", "xyz (m)", "rpy (rad)"]);
        for frame in model.frames() {
            let (xyz, rpy) = pose(&frame.placement);
            frames.row(vec![
                frame.name.clone(),
                model.link(frame.link).name.clone(),
                xyz,
                rpy,
            ]);
        }
        let _ = write!(out, "{frames}");
    }

    let _ = writeln!(
        out,
        "\nignored elements ({}, not modelled by kinetree):",
        model.ignored().len()
    );
    list(&mut out, model.ignored().iter());
    let _ = writeln!(out, "\nwarnings ({}):", model.warnings().len());
    list(&mut out, model.warnings().iter());
    out
}

/// A composite joint's row: its factors in the axis column (`tx=0.1 ry rz`), its variables'
/// limits as lists, its whole blocks.
fn composite_row(model: &Model, u: usize, c: usize) -> Vec<String> {
    use kinetree::model::composite::Factor;
    let spec = &model.composites()[c].spec;
    let factors: Vec<String> = spec
        .factors
        .iter()
        .map(|f| match f {
            Factor::Translate(_, Some(x)) | Factor::Rotate(_, Some(x)) => {
                format!("{}={}", f.param(), num(*x))
            }
            Factor::Rotation(r) => format!("quat={:?}", r.to_array().map(num)),
            _ => f.param(),
        })
        .collect();
    let pieces = model.user_joints()[u].joints.clone();
    let scalar = pieces
        .clone()
        .map(|j| model.joint(j))
        .filter(|j| j.kind.nq() == 1)
        .collect::<Vec<_>>();
    let list = |pick: &dyn Fn(&kinetree::model::JointLimits) -> f64| {
        let v: Vec<String> = scalar.iter().map(|j| num(pick(&j.limits))).collect();
        if v.is_empty() {
            "-".to_string()
        } else {
            v.join(",")
        }
    };
    let (q, v) = (model.user_joint_q_range(u), model.user_joint_v_range(u));
    let index = |r: core::ops::Range<usize>| {
        if r.is_empty() {
            "-".to_string()
        } else {
            format!("{}..{}", r.start, r.end)
        }
    };
    let parent = model
        .joint(pieces.start)
        .parent_link
        .map_or("world", |p| model.link(p).name.as_str());
    vec![
        spec.name.clone(),
        "composite".into(),
        format!("{parent} → {}", spec.child),
        factors.join(" "),
        list(&|l| l.lower),
        list(&|l| l.upper),
        list(&|l| l.velocity),
        list(&|l| l.effort),
        index(q),
        index(v),
    ]
}

fn list<T: std::fmt::Display>(out: &mut String, items: impl ExactSizeIterator<Item = T>) {
    if items.len() == 0 {
        let _ = writeln!(out, "  none");
    }
    for item in items {
        let _ = writeln!(out, "  {item}");
    }
}

/// A number as short as it can be read back: integers without a fraction, infinities as `inf`,
/// and long fractions cut to 6 decimals.
fn num(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    let x = if x == 0.0 { 0.0 } else { x }; // no "-0"
    let s = format!("{x}");
    if s.len() <= 10 {
        return s;
    }
    let cut = format!("{x:.6}");
    let cut = cut.trim_end_matches('0').trim_end_matches('.');
    if cut == "-0" { "0" } else { cut }.to_string()
}

fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

fn pose(t: &Se3) -> (String, String) {
    (vec3(t.translation.to_array()), vec3(t.to_rpy()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_exact_where_possible() {
        assert_eq!(num(87.0), "87");
        assert_eq!(num(-2.8973), "-2.8973");
        assert_eq!(num(f64::INFINITY), "inf");
        assert_eq!(num(f64::NEG_INFINITY), "-inf");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(0.1 + 0.2), "0.3");
        assert_eq!(num(std::f64::consts::FRAC_1_SQRT_2), "0.707107");
        assert_eq!(num(-1e-12), "0");
        assert_eq!(vec3([0.0, -1.0, 0.5]), "[0, -1, 0.5]");
    }
}
