//! [`assert_close!`](crate::assert_close): float comparison with the project's tolerances.

use kinetree_kinematics::spatial::DVec3;

/// Absolute part of the reference files' suggested tolerance ("1e-9 absolute + 1e-9 relative
/// for kinematics/dynamics").
pub const ABS_TOL: f64 = 1e-9;
/// Relative part of the reference files' suggested tolerance.
pub const REL_TOL: f64 = 1e-9;

/// Values [`assert_close!`](crate::assert_close) compares entry by entry.
pub trait Close {
    /// The entries, in order.
    fn entries(&self) -> Vec<f64>;
}

impl Close for f64 {
    fn entries(&self) -> Vec<f64> {
        vec![*self]
    }
}

impl Close for [f64] {
    fn entries(&self) -> Vec<f64> {
        self.to_vec()
    }
}

impl<const N: usize> Close for [f64; N] {
    fn entries(&self) -> Vec<f64> {
        self.to_vec()
    }
}

impl Close for Vec<f64> {
    fn entries(&self) -> Vec<f64> {
        self.clone()
    }
}

impl Close for DVec3 {
    fn entries(&self) -> Vec<f64> {
        self.to_array().to_vec()
    }
}

impl<T: Close + ?Sized> Close for &T {
    fn entries(&self) -> Vec<f64> {
        (**self).entries()
    }
}

/// Whether `|actual - expected| <= abs + rel·|expected|` (false when either is NaN).
fn is_close(actual: f64, expected: f64, abs: f64, rel: f64) -> bool {
    (actual - expected).abs() <= abs + rel * expected.abs()
}

/// The first entry where `|actual - expected| > abs + rel·|expected|` (or a length mismatch),
/// as a message; `None` when every entry is close.
#[doc(hidden)]
pub fn mismatch(actual: &[f64], expected: &[f64], abs: f64, rel: f64) -> Option<String> {
    if actual.len() != expected.len() {
        return Some(format!(
            "{} entries, expected {}",
            actual.len(),
            expected.len()
        ));
    }
    actual
        .iter()
        .zip(expected)
        .enumerate()
        .find(|(_, (a, e))| !is_close(**a, **e, abs, rel))
        .map(|(i, (a, e))| {
            format!(
                "entry {i}: {a} vs {e} (difference {:e}, tolerance {abs:e} + {rel:e}·|expected|)",
                (a - e).abs()
            )
        })
}

/// Asserts that two numbers, slices, arrays, `Vec`s or `DVec3`s agree entry by entry:
/// `assert_close!(actual, expected)` within [`ABS_TOL`](crate::ABS_TOL) +
/// [`REL_TOL`](crate::REL_TOL)·|expected|, `assert_close!(actual, expected, abs)` within an
/// absolute tolerance, `assert_close!(actual, expected, abs, rel)` within both; an optional
/// trailing format string and arguments name what is compared. NaN is never close.
#[macro_export]
macro_rules! assert_close {
    ($actual:expr, $expected:expr $(,)?) => {
        $crate::assert_close!($actual, $expected, $crate::ABS_TOL, $crate::REL_TOL, "")
    };
    ($actual:expr, $expected:expr, $abs:expr $(,)?) => {
        $crate::assert_close!($actual, $expected, $abs, 0.0, "")
    };
    ($actual:expr, $expected:expr, $abs:expr, $rel:expr $(,)?) => {
        $crate::assert_close!($actual, $expected, $abs, $rel, "")
    };
    ($actual:expr, $expected:expr, $abs:expr, $rel:expr, $($what:tt)+) => {{
        let (actual, expected) = (
            $crate::Close::entries(&($actual)),
            $crate::Close::entries(&($expected)),
        );
        if let Some(why) = $crate::close_mismatch(&actual, &expected, $abs, $rel) {
            panic!(
                "assert_close!({}, {}) {}: {}",
                stringify!($actual),
                stringify!($expected),
                format!($($what)+),
                why
            );
        }
    }};
}
