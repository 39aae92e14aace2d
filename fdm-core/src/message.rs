//! How messages show what they quote: numbers in a short form
//! ([`ShortNumber`]), in every build (no allocation, `no_std`).

use core::fmt;

/// A number as messages show it: Rust's shortest form when that is at most
/// [`ShortNumber::MAX_CHARS`] characters, else scientific notation (`1e308`,
/// not 309 digits). Writes nothing on the heap (no_std).
///
/// ```
/// use fdm_core::message::ShortNumber;
/// assert_eq!(ShortNumber(2000.5).to_string(), "2000.5");
/// assert_eq!(ShortNumber(1e308).to_string(), "1e308");
/// assert_eq!(ShortNumber(-1.5e300).to_string(), "-1.5e300");
/// assert_eq!(ShortNumber(f64::NAN).to_string(), "NaN");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShortNumber(pub f64);

impl ShortNumber {
    /// Longest plain form shown; longer numbers are shown in scientific notation.
    pub const MAX_CHARS: usize = 24;
}

impl fmt::Display for ShortNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        /// Counts the characters of the plain form without storing them.
        struct Count(usize);
        impl fmt::Write for Count {
            fn write_str(&mut self, s: &str) -> fmt::Result {
                self.0 += s.len();
                Ok(())
            }
        }
        let mut plain = Count(0);
        fmt::Write::write_fmt(&mut plain, format_args!("{}", self.0))?;
        if plain.0 <= Self::MAX_CHARS {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
