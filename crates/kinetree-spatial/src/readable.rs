//! [`Readable`]: a number as a message should print it, so that an error about `1e308` never
//! prints a 309-digit decimal.

/// A number for messages: plain decimal notation from 1e-4 to below 1e9 (and for zero, NaN and
/// the infinities), scientific notation outside (`1e308`, `2.5e-12`). A precision applies to
/// either form (`{:.3}` gives `0.125` or `1.000e12`).
///
/// # Examples
/// ```
/// use kinetree_spatial::Readable;
/// assert_eq!(Readable(0.25).to_string(), "0.25");
/// assert_eq!(Readable(1e308).to_string(), "1e308");
/// assert_eq!(Readable(-1e-300).to_string(), "-1e-300");
/// assert_eq!(format!("{:.3}", Readable(1e300)), "1.000e300");
/// assert_eq!(format!("{:.3}", Readable(2.0)), "2.000");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readable(pub f64);

impl core::fmt::Display for Readable {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let x = self.0;
        let plain = x == 0.0 || !x.is_finite() || (1e-4..1e9).contains(&x.abs());
        match (plain, f.precision()) {
            (true, Some(p)) => write!(f, "{x:.p$}"),
            (true, None) => write!(f, "{x}"),
            (false, Some(p)) => write!(f, "{x:.p$e}"),
            (false, None) => write!(f, "{x:e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Readable;

    #[test]
    fn large_and_small_numbers_are_scientific_others_plain() {
        for (x, s) in [
            (0.0, "0"),
            (-0.0, "-0"),
            (1.5, "1.5"),
            (123_456_789.0, "123456789"),
            (1e9, "1e9"),
            (1e-4, "0.0001"),
            (9.9e-5, "9.9e-5"),
            (5e-324, "5e-324"),
            (f64::MAX, "1.7976931348623157e308"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(Readable(x).to_string(), s);
        }
        assert_eq!(format!("{:.2}", Readable(-1e-300)), "-1.00e-300");
    }
}
