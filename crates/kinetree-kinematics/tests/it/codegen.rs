//! Generated forward kinematics (trip_kinematics' `get_symbolic_rep`): the Rust and C sources
//! compiled and run, the Python evaluated with floats and as SymPy expressions, all against
//! `forward_kinematics` at random states to 1e-12.

use kinetree_kinematics::codegen::{Lang, generate, identifier};
use kinetree_kinematics::configuration::random_configuration;
use kinetree_kinematics::model::{LoadOptions, MimicMode, Model, RootJoint, samples};
use kinetree_kinematics::{
    FrameId, KinematicsData, KinematicsError, forward_kinematics, update_frame_placements,
};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use std::path::PathBuf;
use std::process::Command;

/// A model, the frame to generate, and the states to check.
struct Case {
    tag: &'static str,
    model: Model,
    frame: FrameId,
    states: Vec<Vec<f64>>,
}

fn case(tag: &'static str, model: Model, frame: &str, seed: u64) -> Case {
    let frame = FrameId::find(&model, frame).unwrap();
    let mut rng = SmallRng::seed_from_u64(seed);
    let states = (0..5)
        .map(|_| {
            let mut q = vec![0.0; model.nq()];
            random_configuration(&model, &mut rng, &mut q).unwrap();
            q
        })
        .collect();
    Case {
        tag,
        model,
        frame,
        states,
    }
}

/// The joint kinds on the path from the world to `frame`.
fn kinds_on_path(model: &Model, frame: FrameId) -> std::collections::BTreeSet<String> {
    let mut kinds = std::collections::BTreeSet::new();
    let (mut b, _) = frame.body(model).unwrap();
    while b != 0 {
        kinds.insert(format!("{:?}", model.bodies()[b].kind));
        b = model.bodies()[b].parent;
    }
    kinds
}

/// The link of a random tree with the most joint kinds on its path.
fn most_varied_link(model: &Model) -> String {
    (0..model.links().len())
        .max_by_key(|&l| kinds_on_path(model, FrameId::Link(l)).len())
        .map(|l| model.link(l).name.clone())
        .unwrap()
}

fn cases() -> Vec<Case> {
    let panda = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    let coupled = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::from(RootJoint::Fixed)
    };
    // Every joint kind: random trees (revolute, continuous, prismatic, cylindrical, spherical,
    // planar, fixed, arbitrary axes) on a floating root.
    let tree = |seed| samples::random_tree_with_root(seed, 14, RootJoint::Floating);
    vec![
        case(
            "panda",
            Model::from_urdf_file(panda, RootJoint::Fixed).unwrap(),
            "panda_hand_tcp",
            1,
        ),
        // The right finger moves with the left one's coordinate (a coupled mimic joint).
        case(
            "panda_mimic",
            Model::from_urdf_file_with(panda, &coupled).unwrap(),
            "panda_rightfinger",
            2,
        ),
        case("tree_a", tree(3), &most_varied_link(&tree(3)), 3),
        case("tree_b", tree(8), &most_varied_link(&tree(8)), 4),
        case("tree_c", tree(6), &most_varied_link(&tree(6)), 6),
        case("planar", samples::planar_2r(0.3, 0.2), "tool", 5),
    ]
}

/// `world_from_frame` as the row-major 4×4 the generated code returns.
fn expected(c: &Case, q: &[f64]) -> [f64; 16] {
    let mut data = KinematicsData::new(&c.model);
    forward_kinematics(&c.model, &mut data, q).unwrap();
    update_frame_placements(&c.model, &mut data).unwrap();
    let x = data.world_from(c.frame).unwrap();
    let mut m = [0.0; 16];
    for i in 0..3 {
        for j in 0..3 {
            m[4 * i + j] = x.rotation.col(j)[i];
        }
        m[4 * i + 3] = x.translation[i];
    }
    m[15] = 1.0;
    m
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("kinetree-codegen-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Compares the printed numbers (16 per state) with forward kinematics.
fn check(c: &Case, what: &str, printed: &str) {
    let values: Vec<f64> = printed
        .split_whitespace()
        .map(|x| x.parse().unwrap_or_else(|_| panic!("{what}: '{x}'")))
        .collect();
    assert_eq!(values.len(), 16 * c.states.len(), "{what}: {printed}");
    let mut worst: f64 = 0.0;
    for (q, got) in c.states.iter().zip(values.chunks(16)) {
        for (a, b) in expected(c, q).iter().zip(got) {
            worst = worst.max((a - b).abs());
        }
    }
    assert!(
        worst < 1e-12,
        "{} {what}: worst difference {worst:e}",
        c.tag
    );
}

fn literal_states(c: &Case, open: &str, close: &str) -> String {
    c.states
        .iter()
        .map(|q| {
            let xs: Vec<String> = q.iter().map(|x| format!("{x:?}")).collect();
            format!("{open}{}{close}", xs.join(", "))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn the_cases_cover_every_joint_kind() {
    let mut kinds = std::collections::BTreeSet::new();
    for c in cases() {
        kinds.extend(kinds_on_path(&c.model, c.frame));
    }
    assert_eq!(kinds.len(), 7, "{kinds:?}"); // every moving kind
}

#[test]
fn generated_rust_compiles_and_matches_forward_kinematics() {
    for c in cases() {
        rust_matches(&c, &format!("fk_{}", c.tag));
    }
}

/// The Rust source of `c` as function `name`, compiled with warnings denied and run on the
/// case's states: the numbers match forward kinematics.
fn rust_matches(c: &Case, name: &str) {
    let mut src = generate(&c.model, c.frame, Lang::Rust, name).unwrap();
    src.push_str(&format!(
        "\nfn main() {{\n    let states: Vec<Vec<f64>> = vec![{}];\n    for q in &states {{\n        for row in {name}(q) {{\n            for x in row {{\n                println!(\"{{x:?}}\");\n            }}\n        }}\n    }}\n}}\n",
        literal_states(c, "vec![", "]")
    ));
    let file = dir().join(format!("{name}.rs"));
    let exe = dir().join(format!("{name}_rs"));
    std::fs::write(&file, &src).unwrap();
    run(Command::new("rustc")
        .args(["--edition", "2021", "-O", "-D", "warnings", "-o"])
        .arg(&exe)
        .arg(&file));
    check(c, "rust", &run(&mut Command::new(&exe)));
}

#[test]
fn generated_c_compiles_and_matches_forward_kinematics() {
    for c in cases() {
        c_matches(&c, &format!("fk_{}", c.tag));
    }
}

/// As [`rust_matches`], in C (`-Wall -Werror`).
fn c_matches(c: &Case, name: &str) {
    let mut src = generate(&c.model, c.frame, Lang::C, name).unwrap();
    let n = c.states.len();
    let nq = c.model.nq().max(1);
    src.push_str(&format!(
        "\n#include <stdio.h>\nint main(void) {{\n    static const double states[{n}][{nq}] = {{{}}};\n    double out[16];\n    for (int s = 0; s < {n}; s++) {{\n        {name}(states[s], out);\n        for (int k = 0; k < 16; k++) printf(\"%.17g\\n\", out[k]);\n    }}\n    return 0;\n}}\n",
        literal_states(c, "{", "}")
    ));
    let file = dir().join(format!("{name}.c"));
    let exe = dir().join(format!("{name}_c"));
    std::fs::write(&file, &src).unwrap();
    run(Command::new("cc")
        .args(["-std=c99", "-O2", "-Wall", "-Werror", "-o"])
        .arg(&exe)
        .arg(&file)
        .arg("-lm"));
    check(c, "c", &run(&mut Command::new(&exe)));
}

#[test]
fn generated_python_evaluates_with_floats_and_as_sympy_expressions() {
    for c in cases() {
        python_matches(&c, &format!("fk_{}", c.tag));
    }
}

/// As [`rust_matches`], in Python: with floats and through the SymPy matrix.
fn python_matches(c: &Case, name: &str) {
    let src = generate(&c.model, c.frame, Lang::Python, name).unwrap();
    let file = dir().join(format!("{name}.py"));
    std::fs::write(&file, &src).unwrap();
    let states = literal_states(c, "[", "]");
    // Plain floats.
    let floats = format!(
        "import runpy\nm = runpy.run_path({file:?})\nfor q in [{states}]:\n    for row in m['{name}'](q):\n        for x in row:\n            print(repr(float(x)))\n",
        file = file.display().to_string()
    );
    check(
        c,
        "python floats",
        &run(Command::new("python3").args(["-c", &floats])),
    );
    // The SymPy expression: a matrix in the symbols q0.., evaluated by substitution.
    let symbolic = format!(
        "import runpy, sympy\nm = runpy.run_path({file:?})\nM, syms = m['{name}_sympy']()\nassert isinstance(M, sympy.Matrix) and M.shape == (4, 4)\nassert all(e.free_symbols <= set(syms) for e in M)\nf = sympy.lambdify(syms, M.tolist(), modules='math')\nfor q in [{states}]:\n    for row in f(*q):\n        for x in row:\n            print(repr(float(x)))\n",
        file = file.display().to_string()
    );
    check(
        c,
        "python sympy",
        &run(Command::new("python3").args(["-c", &symbolic])),
    );
}

#[test]
fn only_the_path_is_in_the_code_and_names_are_identifiers() {
    let arm = samples::planar_2r(0.3, 0.2);
    let tool = FrameId::find(&arm, "tool").unwrap();
    let src = generate(&arm, tool, Lang::Rust, &identifier("tool pose")).unwrap();
    assert!(
        src.contains("pub fn tool_pose(q: &[f64]) -> [[f64; 4]; 4]"),
        "{src}"
    );
    assert_eq!(src.matches("f64::sin(").count(), 2, "{src}");
    assert_eq!(src.matches("f64::cos(").count(), 2, "{src}");
    // The base frame of the arm does not depend on q: a constant matrix, no statement.
    let base = FrameId::find(&arm, "base").unwrap();
    let src = generate(&arm, base, Lang::C, "base").unwrap();
    assert!(!src.contains("sin("), "{src}");
    assert!(src.contains("out[15] = 1.0;"), "{src}");
    assert_eq!(identifier("9 lives/x-y"), "_9_lives_x_y");
    let e = generate(&arm, FrameId::Frame(99), Lang::Python, "f").unwrap_err();
    assert!(e.to_string().contains("99"), "{e}");
}

/// A model whose names are hostile to every comment syntax, its tool frame among them.
fn hostile_model() -> Model {
    let urdf = r#"<robot name="m */ /* \N &quot;&quot;&quot; ??/ &#10;&#13;&#x2028; \">
      <link name="base"/>
      <link name="x*/ a\x a\N{DEL} a&quot;&quot;&quot;b &lt;!--&lt;script&gt; &#10;#define ü \">
        <inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
      </link>
      <joint name="j" type="revolute"><parent link="base"/>
        <child link="x*/ a\x a\N{DEL} a&quot;&quot;&quot;b &lt;!--&lt;script&gt; &#10;#define ü \"/>
        <origin xyz="0.1 0.2 0.3" rpy="0.3 0.2 0.1"/><axis xyz="0.6 0 0.8"/>
        <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
    </robot>"#;
    Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap()
}

#[test]
fn hostile_frame_and_model_names_stay_inside_the_comments() {
    let model = hostile_model();
    let link = model.links()[1].name.clone();
    assert!(link.contains("*/") && link.contains('\n') && link.contains("\"\"\""));
    let c = case("hostile", model, &link, 11);
    // Each compiles with warnings denied and computes forward kinematics.
    rust_matches(&c, "fk_hostile");
    c_matches(&c, "fk_hostile");
    python_matches(&c, "fk_hostile");
}

#[test]
fn names_the_language_cannot_use_are_refused_by_name() {
    let arm = samples::planar_2r(0.3, 0.2);
    let tool = FrameId::find(&arm, "tool").unwrap();
    let refused = [
        (Lang::C, "int"),
        (Lang::C, "sin"),
        (Lang::C, "sqrtf"),
        (Lang::C, "main"),
        (Lang::Python, "None"),
        (Lang::Python, "math"),
        (Lang::Python, "lambda"),
        (Lang::Rust, "fn"),
        (Lang::Rust, "_"),
        (Lang::Rust, "ü"),
        (Lang::C, "pose-1"),
        (Lang::Python, "1pose"),
        (Lang::Rust, ""),
        (Lang::C, "a*/b"),
    ];
    for (lang, name) in refused {
        let e = generate(&arm, tool, lang, name).unwrap_err();
        assert!(
            matches!(&e, KinematicsError::InvalidCodegenName { name: n, .. } if n == name),
            "{lang:?} {name:?}: {e}"
        );
        assert!(e.to_string().contains(lang.name()), "{e}");
    }
    // What one language reserves another may use: these compile and compute.
    let c = case("names", arm, "tool", 12);
    rust_matches(&c, "sin");
    python_matches(&c, "sin");
    c_matches(&c, "sinus");
    rust_matches(&c, "int");
}

#[test]
fn constants_too_large_for_f64_are_refused_as_forward_kinematics_refuses_them() {
    let urdf = r#"<robot name="far"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="ab" type="fixed"><parent link="a"/><child link="b"/><origin xyz="1e308 0 0"/></joint>
      <joint name="bc" type="revolute"><parent link="b"/><child link="c"/><origin xyz="1e308 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let model = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap();
    let mut data = KinematicsData::new(&model);
    let fk = forward_kinematics(&model, &mut data, &[0.0]).unwrap_err();
    assert!(matches!(fk, KinematicsError::Overflow { .. }), "{fk}");
    let frame = FrameId::find(&model, "c").unwrap();
    for lang in [Lang::Rust, Lang::C, Lang::Python] {
        let e = generate(&model, frame, lang, "far").unwrap_err();
        assert!(
            matches!(&e, KinematicsError::Overflow { body, .. } if body == "c"),
            "{lang:?}: {e}"
        );
    }
    // The frame on the near side is still generated.
    let b = FrameId::find(&model, "b").unwrap();
    let src = generate(&model, b, Lang::C, "near").unwrap();
    assert!(src.contains("out[3] = 1e308;"), "{src}");
}
