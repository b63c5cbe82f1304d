//! Forward kinematics of one frame as source code (trip_kinematics' `get_symbolic_rep`): the
//! frame's world pose as straight-line code in the joint variables, for Rust, C or Python.
//!
//! The generated function takes the whole configuration `q` (length `model.nq()`, in the model's
//! order) and returns the 4×4 homogeneous matrix `world_from_frame`, row-major. Only the joints
//! on the frame's path appear; constant parts (placements, fixed joints, axis-aligned axes) are
//! folded at generation time, so the code holds only the arithmetic that depends on `q`.
//! Constant entries smaller than 1e-15 (rounding left by `rpy` angles of ±π/2) are written as
//! zero. Quaternion blocks (ball and free joints) are normalised as [`forward_kinematics`] does; the
//! generated code does not check them (a zero quaternion gives NaN).
//!
//! - [`Lang::Rust`]: `pub fn NAME(q: &[f64]) -> [[f64; 4]; 4]` (panics if `q` is shorter than
//!   `model.nq()`, as slice indexing does).
//! - [`Lang::C`]: `void NAME(const double *q, double out[16])`, with `#include <math.h>`.
//! - [`Lang::Python`]: `NAME_expr(q, sin, cos, sqrt)` builds the 4×4 nested list from any
//!   numbers or symbols with arithmetic operators (SymPy symbols, CasADi `SX`), `NAME(q)` is
//!   plain floats with `math`, and `NAME_sympy()` / `NAME_casadi()` return the symbolic matrix
//!   and its symbols (importing SymPy or CasADi when called).
//!
//! [`forward_kinematics`]: crate::forward_kinematics
//!
//! # Examples
//! ```
//! use kinetree_kinematics::codegen::{Lang, generate};
//! use kinetree_kinematics::model::samples;
//! use kinetree_kinematics::FrameId;
//! # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
//! let arm = samples::planar_2r(0.3, 0.2);
//! let tool = FrameId::find(&arm, "tool")?;
//! let c = generate(&arm, tool, Lang::C, "tool_pose")?;
//! assert!(c.contains("void tool_pose(const double *q, double out[16])"));
//! assert!(c.contains("sin(q[0])"));
//! # Ok(())
//! # }
//! ```

use crate::data::FrameId;
use crate::error::KinematicsError;
use crate::joint::JointModel;
use glam::{DMat3, DVec3};
use kinetree_model::Model;
use std::cell::Cell;
use std::fmt::Write as _;

/// The language of the generated code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    /// A Rust function.
    Rust,
    /// A C99 function.
    C,
    /// Python: a function over any arithmetic (SymPy, CasADi) and a plain-float one.
    Python,
}

/// A scalar while generating: a number known now, or a name in the generated code.
#[derive(Clone, Debug, PartialEq)]
enum V {
    Const(f64),
    Name(String),
}

impl V {
    fn is(&self, x: f64) -> bool {
        matches!(self, V::Const(c) if *c == x)
    }
}

/// The statements generated so far.
struct Emitter {
    lang: Lang,
    lines: Vec<String>,
    temps: usize,
    /// Whether a literal written so far is not finite (the model's constants overflowed).
    overflowed: Cell<bool>,
}

impl Emitter {
    fn lit(&self, x: f64) -> String {
        if !x.is_finite() {
            self.overflowed.set(true);
        }
        // `{:?}` prints the shortest text that reads back to the same f64 ("1.0", "1e-5").
        let s = format!("{x:?}");
        if x < 0.0 { format!("({s})") } else { s }
    }

    fn text(&self, v: &V) -> String {
        match v {
            V::Const(x) => self.lit(*x),
            V::Name(n) => n.clone(),
        }
    }

    fn bind(&mut self, expr: String) -> V {
        let name = format!("t{}", self.temps);
        self.temps += 1;
        self.lines.push(expr);
        V::Name(name)
    }

    /// The statements that `results` need (the others dropped), in the target language.
    fn statements(&self, results: &[String]) -> String {
        let temps_in = |text: &str| -> Vec<usize> {
            let b = text.as_bytes();
            let mut out = Vec::new();
            for (i, &c) in b.iter().enumerate() {
                let starts = c == b't'
                    && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
                if starts {
                    let digits: String = text[i + 1..]
                        .chars()
                        .take_while(char::is_ascii_digit)
                        .collect();
                    if let Ok(k) = digits.parse() {
                        out.push(k);
                    }
                }
            }
            out
        };
        let mut live = vec![false; self.lines.len()];
        for r in results {
            for k in temps_in(r) {
                live[k] = true;
            }
        }
        for k in (0..self.lines.len()).rev() {
            if live[k] {
                for d in temps_in(&self.lines[k]) {
                    live[d] = true;
                }
            }
        }
        let mut out = Vec::new();
        for (k, expr) in self.lines.iter().enumerate().filter(|(k, _)| live[*k]) {
            out.push(match self.lang {
                Lang::Rust => format!("    let t{k}: f64 = {expr};"),
                Lang::C => format!("    const double t{k} = {expr};"),
                Lang::Python => format!("    t{k} = {expr}"),
            });
        }
        out.join("\n")
    }

    fn call(&mut self, f: &str, x: &V) -> V {
        let arg = self.text(x);
        let expr = match self.lang {
            Lang::Rust => format!("f64::{f}({arg})"),
            Lang::C | Lang::Python => format!("{f}({arg})"),
        };
        self.bind(expr)
    }

    fn func(&mut self, f: fn(f64) -> f64, name: &str, x: &V) -> V {
        match x {
            V::Const(c) => V::Const(f(*c)),
            V::Name(_) => self.call(name, x),
        }
    }

    fn add(&mut self, a: &V, b: &V) -> V {
        match (a, b) {
            (V::Const(x), V::Const(y)) => V::Const(x + y),
            _ if a.is(0.0) => b.clone(),
            _ if b.is(0.0) => a.clone(),
            _ => {
                let e = format!("{} + {}", self.text(a), self.text(b));
                self.bind(e)
            }
        }
    }

    fn sub(&mut self, a: &V, b: &V) -> V {
        match (a, b) {
            (V::Const(x), V::Const(y)) => V::Const(x - y),
            _ if b.is(0.0) => a.clone(),
            _ => {
                let e = format!("{} - {}", self.text(a), self.text(b));
                self.bind(e)
            }
        }
    }

    fn mul(&mut self, a: &V, b: &V) -> V {
        match (a, b) {
            (V::Const(x), V::Const(y)) => V::Const(x * y),
            _ if a.is(0.0) || b.is(0.0) => V::Const(0.0),
            _ if a.is(1.0) => b.clone(),
            _ if b.is(1.0) => a.clone(),
            _ if a.is(-1.0) => {
                let e = format!("-{}", self.text(b));
                self.bind(e)
            }
            _ if b.is(-1.0) => {
                let e = format!("-{}", self.text(a));
                self.bind(e)
            }
            _ => {
                let e = format!("{} * {}", self.text(a), self.text(b));
                self.bind(e)
            }
        }
    }

    fn div(&mut self, a: &V, b: &V) -> V {
        match (a, b) {
            (V::Const(x), V::Const(y)) => V::Const(x / y),
            _ if a.is(0.0) => V::Const(0.0),
            _ => {
                let e = format!("{} / {}", self.text(a), self.text(b));
                self.bind(e)
            }
        }
    }

    /// Σ aᵢ·bᵢ.
    fn dot(&mut self, a: &[V], b: &[V]) -> V {
        let mut sum = V::Const(0.0);
        for (x, y) in a.iter().zip(b) {
            let p = self.mul(x, y);
            sum = self.add(&sum, &p);
        }
        sum
    }
}

/// Constant entries (of placements) smaller than this are written as zero.
const SNAP: f64 = 1e-15;

/// A pose in the generated code: rotation `r[row][col]` and translation `t`.
#[derive(Clone, Debug)]
struct Pose {
    r: [[V; 3]; 3],
    t: [V; 3],
}

impl Pose {
    /// Whether every entry known at generation time is finite.
    fn constants_finite(&self) -> bool {
        self.r
            .iter()
            .flatten()
            .chain(&self.t)
            .all(|v| !matches!(v, V::Const(x) if !x.is_finite()))
    }

    /// A constant pose, with entries below [`SNAP`] in magnitude written as zero (the
    /// `6.1e-17` that `cos(π/2)` leaves in a URDF's `rpy`), so expressions stay readable.
    fn constant(rotation: &DMat3, translation: DVec3) -> Self {
        let snap = |x: f64| V::Const(if x.abs() < SNAP { 0.0 } else { x });
        Self {
            r: std::array::from_fn(|i| std::array::from_fn(|j| snap(rotation.col(j)[i]))),
            t: std::array::from_fn(|i| snap(translation[i])),
        }
    }

    fn identity() -> Self {
        Self::constant(&DMat3::IDENTITY, DVec3::ZERO)
    }

    /// `self * other`.
    fn then(&self, e: &mut Emitter, other: &Pose) -> Pose {
        let r = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let col: Vec<V> = (0..3).map(|k| other.r[k][j].clone()).collect();
                e.dot(&self.r[i], &col)
            })
        });
        let t = std::array::from_fn(|i| {
            let rt = e.dot(&self.r[i], &other.t);
            e.add(&self.t[i], &rt)
        });
        Pose { r, t }
    }
}

/// The rotation by `angle` about the unit `axis` (Rodrigues), exact for the coordinate axes.
fn axis_rotation(e: &mut Emitter, axis: DVec3, angle: &V) -> [[V; 3]; 3] {
    let s = e.func(f64::sin, "sin", angle);
    let c = e.func(f64::cos, "cos", angle);
    let one_minus_c = e.sub(&V::Const(1.0), &c);
    let a = axis.to_array();
    let exact_axis = a.iter().filter(|x| **x == 0.0).count() == 2;
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            if exact_axis {
                if i == j {
                    return if a[i] == 0.0 {
                        c.clone()
                    } else {
                        V::Const(1.0)
                    };
                }
                let k = 3 - i - j;
                return if a[k] == 0.0 {
                    V::Const(0.0)
                } else {
                    // [a]× entry (i, j) is -ε_ijk a_k: s·a_k with the sign of the permutation.
                    let sign = if (i + 1) % 3 == j { -a[k] } else { a[k] };
                    e.mul(&V::Const(sign), &s)
                };
            }
            let outer = e.mul(&one_minus_c, &V::Const(a[i] * a[j]));
            let base = if i == j { e.add(&c, &outer) } else { outer };
            if i == j {
                base
            } else {
                let k = 3 - i - j;
                let sign = if (i + 1) % 3 == j { -a[k] } else { a[k] };
                let cross = e.mul(&V::Const(sign), &s);
                e.add(&base, &cross)
            }
        })
    })
}

/// The rotation of the quaternion `(x, y, z, w)` after normalising it.
fn quat_rotation(e: &mut Emitter, q: [V; 4]) -> [[V; 3]; 3] {
    let sq = e.dot(&q, &q);
    let n = e.func(f64::sqrt, "sqrt", &sq);
    let [x, y, z, w] = q.map(|c| e.div(&c, &n));
    let two = V::Const(2.0);
    let mut m = |a: &V, b: &V| {
        let p = e.mul(a, b);
        e.mul(&two, &p)
    };
    let (xx, yy, zz) = (m(&x, &x), m(&y, &y), m(&z, &z));
    let (xy, xz, yz) = (m(&x, &y), m(&x, &z), m(&y, &z));
    let (wx, wy, wz) = (m(&w, &x), m(&w, &y), m(&w, &z));
    let one = V::Const(1.0);
    let mut diag = |a: &V, b: &V| {
        let s = e.add(a, b);
        e.sub(&one, &s)
    };
    let (d0, d1, d2) = (diag(&yy, &zz), diag(&xx, &zz), diag(&xx, &yy));
    [
        [d0, e.sub(&xy, &wz), e.add(&xz, &wy)],
        [e.add(&xy, &wz), d1, e.sub(&yz, &wx)],
        [e.sub(&xz, &wy), e.add(&yz, &wx), d2],
    ]
}

fn q_var(i: usize) -> V {
    V::Name(format!("q[{i}]"))
}

/// The joint motion `joint_from_child` of `jm` in the generated code, for the joint's
/// coordinates `q` (a 1-DoF mimic joint's coordinate already mapped).
fn joint_motion(e: &mut Emitter, jm: &JointModel, q: &[V]) -> Pose {
    let zero = || std::array::from_fn(|_| V::Const(0.0));
    let along = |e: &mut Emitter, a: DVec3, x: &V| -> [V; 3] {
        std::array::from_fn(|i| e.mul(&V::Const(a[i]), x))
    };
    let (r, t) = match *jm {
        JointModel::Fixed => return Pose::identity(),
        JointModel::RevoluteX => (axis_rotation(e, DVec3::X, &q[0]), zero()),
        JointModel::RevoluteY => (axis_rotation(e, DVec3::Y, &q[0]), zero()),
        JointModel::RevoluteZ => (axis_rotation(e, DVec3::Z, &q[0]), zero()),
        JointModel::Revolute(a) => (axis_rotation(e, a, &q[0]), zero()),
        JointModel::PrismaticX => (Pose::identity().r, along(e, DVec3::X, &q[0])),
        JointModel::PrismaticY => (Pose::identity().r, along(e, DVec3::Y, &q[0])),
        JointModel::PrismaticZ => (Pose::identity().r, along(e, DVec3::Z, &q[0])),
        JointModel::Prismatic(a) => (Pose::identity().r, along(e, a, &q[0])),
        JointModel::Cylindrical(a) => (axis_rotation(e, a, &q[1]), along(e, a, &q[0])),
        JointModel::Spherical => (
            quat_rotation(e, [q[0].clone(), q[1].clone(), q[2].clone(), q[3].clone()]),
            zero(),
        ),
        JointModel::Planar { u, w, n } => {
            let r = axis_rotation(e, n, &q[2]);
            let (tu, tw) = (along(e, u, &q[0]), along(e, w, &q[1]));
            (r, std::array::from_fn(|i| e.add(&tu[i], &tw[i])))
        }
        JointModel::Floating => (
            quat_rotation(e, [q[3].clone(), q[4].clone(), q[5].clone(), q[6].clone()]),
            [q[0].clone(), q[1].clone(), q[2].clone()],
        ),
    };
    Pose { r, t }
}

/// Keywords of Rust (strict and reserved, every edition) and `_`, which cannot name a function.
const RUST_RESERVED: &[&str] = &[
    "_", "abstract", "as", "async", "await", "become", "box", "break", "const", "continue",
    "crate", "do", "dyn", "else", "enum", "extern", "false", "final", "fn", "for", "gen", "if",
    "impl", "in", "let", "loop", "macro", "match", "mod", "move", "mut", "override", "priv", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "try", "type",
    "typeof", "unsafe", "unsized", "use", "virtual", "where", "while", "yield",
];

/// Keywords of C (C99 to C23), `main`, and the names `<math.h>` declares (with their `f` and `l`
/// variants) or defines, which the generated C includes.
const C_RESERVED: &[&str] = &[
    "alignas",
    "alignof",
    "auto",
    "bool",
    "break",
    "case",
    "char",
    "const",
    "constexpr",
    "continue",
    "default",
    "do",
    "double",
    "else",
    "enum",
    "extern",
    "false",
    "float",
    "for",
    "goto",
    "if",
    "inline",
    "int",
    "long",
    "main",
    "nullptr",
    "register",
    "restrict",
    "return",
    "short",
    "signed",
    "sizeof",
    "static",
    "static_assert",
    "struct",
    "switch",
    "thread_local",
    "true",
    "typedef",
    "typeof",
    "typeof_unqual",
    "union",
    "unsigned",
    "void",
    "volatile",
    "while",
    "_Alignas",
    "_Alignof",
    "_Atomic",
    "_BitInt",
    "_Bool",
    "_Complex",
    "_Decimal128",
    "_Decimal32",
    "_Decimal64",
    "_Generic",
    "_Imaginary",
    "_Noreturn",
    "_Static_assert",
    "_Thread_local",
    // <math.h>
    "acos",
    "acosh",
    "asin",
    "asinh",
    "atan",
    "atan2",
    "atanh",
    "cbrt",
    "ceil",
    "copysign",
    "cos",
    "cosh",
    "erf",
    "erfc",
    "exp",
    "exp2",
    "expm1",
    "fabs",
    "fdim",
    "floor",
    "fma",
    "fmax",
    "fmin",
    "fmod",
    "frexp",
    "hypot",
    "ilogb",
    "ldexp",
    "lgamma",
    "llrint",
    "llround",
    "log",
    "log10",
    "log1p",
    "log2",
    "logb",
    "lrint",
    "lround",
    "modf",
    "nan",
    "nearbyint",
    "nextafter",
    "nexttoward",
    "pow",
    "remainder",
    "remquo",
    "rint",
    "round",
    "scalbln",
    "scalbn",
    "sin",
    "sinh",
    "sqrt",
    "tan",
    "tanh",
    "tgamma",
    "trunc",
    "fpclassify",
    "isfinite",
    "isgreater",
    "isgreaterequal",
    "isinf",
    "isless",
    "islessequal",
    "islessgreater",
    "isnan",
    "isnormal",
    "isunordered",
    "signbit",
    "HUGE_VAL",
    "HUGE_VALF",
    "HUGE_VALL",
    "INFINITY",
    "NAN",
    "FP_INFINITE",
    "FP_NAN",
    "FP_NORMAL",
    "FP_SUBNORMAL",
    "FP_ZERO",
    "FP_ILOGB0",
    "FP_ILOGBNAN",
    "MATH_ERRNO",
    "MATH_ERREXCEPT",
    "math_errhandling",
    "float_t",
    "double_t",
];

/// Keywords of Python 3 and the module-level names the generated Python uses.
const PYTHON_RESERVED: &[&str] = &[
    "False", "None", "True", "and", "as", "assert", "async", "await", "break", "class", "continue",
    "def", "del", "elif", "else", "except", "finally", "for", "from", "global", "if", "import",
    "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise", "return", "try", "while",
    "with", "yield", "math", "NQ", "range",
];

/// Checks that `name` can name the function [`generate`] writes in `lang`: an ASCII identifier
/// (a letter or `_`, then letters, digits and `_`) that is not a keyword of `lang` or a name
/// the generated code relies on (`<math.h>`'s functions in C, `math` in Python).
///
/// # Errors
/// [`KinematicsError::InvalidCodegenName`] saying why.
///
/// # Examples
/// ```
/// use kinetree_kinematics::codegen::{Lang, check_name};
/// assert!(check_name("tool_pose", Lang::C).is_ok());
/// assert!(check_name("sin", Lang::C).is_err()); // <math.h>'s sin
/// assert!(check_name("sin", Lang::Rust).is_ok());
/// assert!(check_name("fn", Lang::Rust).is_err());
/// assert!(check_name("pose-1", Lang::Python).is_err());
/// ```
pub fn check_name(name: &str, lang: Lang) -> Result<(), KinematicsError> {
    let refuse = |reason: &'static str| {
        Err(KinematicsError::InvalidCodegenName {
            name: name.to_string(),
            lang: lang.name(),
            reason,
        })
    };
    let mut chars = name.chars();
    match chars.next() {
        None => return refuse("it is empty"),
        Some(c) if !(c.is_ascii_alphabetic() || c == '_') => {
            return refuse("it must start with an ASCII letter or '_'");
        }
        Some(_) => {}
    }
    if !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return refuse("it may hold only ASCII letters, digits and '_'");
    }
    let (reserved, what) = match lang {
        Lang::Rust => (RUST_RESERVED, "it is a Rust keyword"),
        Lang::C => (
            C_RESERVED,
            "it is a C keyword or a name of <math.h>, which the code includes",
        ),
        Lang::Python => (
            PYTHON_RESERVED,
            "it is a Python keyword or a name the generated module uses",
        ),
    };
    // `<math.h>` declares `sinf` and `sinl` beside `sin`.
    let base = match lang {
        Lang::C => name
            .strip_suffix(['f', 'l'])
            .filter(|b| C_RESERVED.contains(b) && b.chars().all(|c| c.is_ascii_lowercase()))
            .unwrap_or(name),
        _ => name,
    };
    if reserved.contains(&name) || reserved.contains(&base) {
        return refuse(what);
    }
    Ok(())
}

/// `text` made safe inside the leading comment of `lang`: control characters and the Unicode
/// line and paragraph separators become spaces; in C `*/`, `/*` and `??` (a trigraph's start)
/// are broken apart; in Python (a docstring) `\` and `"` are escaped.
fn comment_text(text: &str, lang: Lang) -> String {
    let flat: String = text
        .chars()
        .map(|c| {
            if c.is_control() || c == '\u{2028}' || c == '\u{2029}' {
                ' '
            } else {
                c
            }
        })
        .collect();
    match lang {
        Lang::Rust => flat,
        Lang::C => {
            // Repeated until stable: breaking one pair may not create another, but `*/*/`
            // needs two passes.
            let mut s = flat;
            loop {
                let t = s
                    .replace("*/", "* /")
                    .replace("/*", "/ *")
                    .replace("??", "? ?");
                if t == s {
                    return s;
                }
                s = t;
            }
        }
        Lang::Python => flat.replace('\\', "\\\\").replace('"', "\\\""),
    }
}

impl Lang {
    /// The language's name in messages: `"Rust"`, `"C"`, `"Python"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Rust => "Rust",
            Self::C => "C",
            Self::Python => "Python",
        }
    }
}

/// `name` made a valid identifier in every target language (other characters become `_`, a
/// leading digit gets a `_` before it).
#[must_use]
pub fn identifier(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

/// The world pose of `frame` as a function named `name` in `lang`; see the
/// [module documentation](self) for the signatures. `name` must be an ASCII identifier that is
/// neither a keyword of `lang` nor a name the generated code uses ([`check_name`]);
/// [`identifier`] makes one of any text. The frame's and the model's names go into the leading
/// comment escaped for it.
///
/// # Errors
/// [`KinematicsError::InvalidCodegenName`] for a `name` [`check_name`] refuses,
/// [`KinematicsError::FrameOutOfRange`] for a frame `model` does not have,
/// [`KinematicsError::Overflow`] when a constant of the code is not finite (placements too
/// large for `f64`, which [`forward_kinematics`](crate::forward_kinematics) refuses too).
pub fn generate(
    model: &Model,
    frame: FrameId,
    lang: Lang,
    name: &str,
) -> Result<String, KinematicsError> {
    check_name(name, lang)?;
    let (body, body_from_frame) = frame.body(model)?;
    let frame_name = frame.name(model)?.to_string();
    let bodies = model.bodies();
    let mut path = Vec::new();
    let mut b = body;
    while b != 0 {
        path.push(b);
        b = bodies[b].parent;
    }
    path.reverse();
    let mut e = Emitter {
        lang,
        lines: Vec::new(),
        temps: 0,
        overflowed: Cell::new(false),
    };
    let mut pose = Pose::identity();
    let mut used = Vec::new();
    for &i in &path {
        let b = &bodies[i];
        let jm = JointModel::from_body(b);
        let q: Vec<V> = match &b.mimic {
            Some(m) => {
                used.push(b.idx_q);
                let scaled = e.mul(&V::Const(m.multiplier), &q_var(b.idx_q));
                vec![e.add(&scaled, &V::Const(m.offset))]
            }
            None => {
                used.extend(b.idx_q..b.idx_q + b.nq);
                (b.idx_q..b.idx_q + b.nq).map(q_var).collect()
            }
        };
        let placement = Pose::constant(&b.placement.rotation, b.placement.translation);
        let motion = joint_motion(&mut e, &jm, &q);
        let local = placement.then(&mut e, &motion);
        pose = pose.then(&mut e, &local);
        if e.overflowed.get() || !pose.constants_finite() {
            return Err(crate::forward::overflow(model, "placement", i));
        }
    }
    let last = Pose::constant(&body_from_frame.rotation, body_from_frame.translation);
    pose = pose.then(&mut e, &last);
    if e.overflowed.get() || !pose.constants_finite() {
        return Err(crate::forward::overflow(model, "placement", body));
    }
    used.sort_unstable();
    used.dedup();
    let nq = model.nq();
    let entries: Vec<String> = (0..3)
        .flat_map(|i| {
            let mut row: Vec<String> = pose.r[i].iter().map(|v| e.text(v)).collect();
            row.push(e.text(&pose.t[i]));
            row
        })
        .chain(["0.0", "0.0", "0.0", "1.0"].map(String::from))
        .collect();
    let body_lines = e.statements(&entries);
    let header = comment_text(
        &format!(
            "World pose of frame '{frame_name}' of model '{}' (generated by kinetree): the 4x4 homogeneous matrix, row-major, of the configuration q (length {nq}; used entries: {used:?}).",
            model.name(),
        ),
        lang,
    );
    let mut out = String::new();
    match lang {
        Lang::Rust => {
            let _ = writeln!(out, "/// {header}");
            let _ = writeln!(out, "#[allow(clippy::all, unused_parens)]");
            let _ = writeln!(out, "#[must_use]");
            let _ = writeln!(out, "pub fn {name}(q: &[f64]) -> [[f64; 4]; 4] {{");
            if !body_lines.is_empty() {
                let _ = writeln!(out, "{body_lines}");
            }
            let rows: Vec<String> = entries
                .chunks(4)
                .map(|r| format!("        [{}]", r.join(", ")))
                .collect();
            let _ = writeln!(out, "    [\n{},\n    ]\n}}", rows.join(",\n"));
        }
        Lang::C => {
            let _ = writeln!(out, "/* {header} */");
            let _ = writeln!(out, "#include <math.h>\n");
            let _ = writeln!(out, "void {name}(const double *q, double out[16]) {{");
            let _ = writeln!(out, "    (void)q;");
            if !body_lines.is_empty() {
                let _ = writeln!(out, "{body_lines}");
            }
            for (k, v) in entries.iter().enumerate() {
                let _ = writeln!(out, "    out[{k}] = {v};");
            }
            let _ = writeln!(out, "}}");
        }
        Lang::Python => {
            let _ = writeln!(out, "\"\"\"{header}\"\"\"\n");
            let _ = writeln!(out, "import math\n\nNQ = {nq}\n\n");
            let _ = writeln!(out, "def {name}_expr(q, sin, cos, sqrt):");
            let _ = writeln!(
                out,
                "    \"\"\"The matrix from q with the given functions: numbers or symbols.\"\"\""
            );
            if !body_lines.is_empty() {
                let _ = writeln!(out, "{body_lines}");
            }
            let rows: Vec<String> = entries
                .chunks(4)
                .map(|r| format!("        [{}]", r.join(", ")))
                .collect();
            let _ = writeln!(out, "    return [\n{},\n    ]\n\n", rows.join(",\n"));
            let _ = writeln!(out, "def {name}(q):");
            let _ = writeln!(out, "    \"\"\"Plain floats (math).\"\"\"");
            let _ = writeln!(
                out,
                "    return {name}_expr(q, math.sin, math.cos, math.sqrt)\n\n"
            );
            // The symbolic front ends differ only in their symbols and the matrix they build.
            let symbolic = [
                (
                    "sympy",
                    "(SymPy Matrix of the pose, the symbols q0 .. q{NQ-1}).",
                    "q = sympy.symbols(f\"q0:{NQ}\") if NQ else ()",
                    "q",
                    "sympy.Matrix(m)",
                ),
                (
                    "casadi",
                    "(CasADi SX 4x4 of the pose, the SX vector q).",
                    "q = casadi.SX.sym(\"q\", NQ)",
                    "[q[i] for i in range(NQ)]",
                    "casadi.vertcat(*[casadi.horzcat(*row) for row in m])",
                ),
            ];
            let functions: Vec<String> = symbolic
                .iter()
                .map(|(module, doc, symbols, args, matrix)| {
                    format!(
                        "def {name}_{module}():\n    \"\"\"{doc}\"\"\"\n    import {module}\n    {symbols}\n    m = {name}_expr({args}, {module}.sin, {module}.cos, {module}.sqrt)\n    return {matrix}, q\n"
                    )
                })
                .collect();
            out.push_str(&functions.join("\n\n"));
        }
    }
    Ok(out)
}
