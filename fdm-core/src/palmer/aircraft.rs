//! Aircraft parameters of the Palmer model and their validation.

use core::fmt;

use crate::message::ShortNumber;

use serde::{Deserialize, Serialize};

/// Mass properties, airfoil and propeller data of a Palmer aircraft (docs/palmer-model.md
/// "Parameters"). Units are part of each field name.
///
/// The defaults ([`PalmerAircraft::cessna_172`], also [`Default`]) are the Cessna
/// 172 Skyhawk values of the book. Aircraft loaded from user files should be
/// checked with [`PalmerAircraft::validate`] before flying.
///
/// ```
/// use fdm_core::palmer::PalmerAircraft;
///
/// let cessna = PalmerAircraft::cessna_172();
/// assert_eq!(cessna.mass_kg, 1114.0);
/// assert!(cessna.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerAircraft {
    /// Wing area, m².
    pub wing_area_m2: f64,
    /// Wing span, m.
    pub wing_span_m: f64,
    /// Tail area, m² (carried for completeness; the equations do not use it).
    pub tail_area_m2: f64,
    /// Slope of the lift coefficient vs. angle of attack line before stall, per degree.
    pub cl_slope0_per_deg: f64,
    /// Lift coefficient at zero angle of attack (dimensionless).
    pub cl0: f64,
    /// Slope of the post-stall lift coefficient line, per degree.
    pub cl_slope1_per_deg: f64,
    /// Intercept of the post-stall lift coefficient line (dimensionless).
    pub cl1: f64,
    /// Angle of attack where the lift coefficient peaks, degrees.
    pub alpha_cl_max_deg: f64,
    /// Parasite drag coefficient (dimensionless).
    pub cdp: f64,
    /// Induced-drag (Oswald) efficiency factor (dimensionless).
    pub eff: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Peak engine power, W.
    pub engine_power_w: f64,
    /// Propeller speed, revolutions per second.
    pub engine_rps: f64,
    /// Propeller diameter, m.
    pub prop_diameter_m: f64,
    /// Propeller efficiency curve fit, constant term `a` (dimensionless).
    pub prop_a: f64,
    /// Propeller efficiency curve fit, coefficient `b` of the squared advance ratio
    /// (dimensionless).
    pub prop_b: f64,
}

impl PalmerAircraft {
    /// The Cessna 172 Skyhawk of the book (the book's default parameters).
    #[must_use]
    pub const fn cessna_172() -> Self {
        Self {
            wing_area_m2: 16.2,
            wing_span_m: 10.9,
            tail_area_m2: 2.0,
            cl_slope0_per_deg: 0.0889,
            cl0: 0.178,
            cl_slope1_per_deg: -0.1,
            cl1: 3.2,
            alpha_cl_max_deg: 16.0,
            cdp: 0.034,
            eff: 0.77,
            mass_kg: 1114.0,
            engine_power_w: 119_310.0,
            engine_rps: 40.0,
            prop_diameter_m: 1.905,
            prop_a: 1.83,
            prop_b: -1.32,
        }
    }

    /// The fields as `(name, value)` pairs, in declaration order.
    const fn fields(&self) -> [(&'static str, f64); 16] {
        [
            ("wing_area_m2", self.wing_area_m2),
            ("wing_span_m", self.wing_span_m),
            ("tail_area_m2", self.tail_area_m2),
            ("cl_slope0_per_deg", self.cl_slope0_per_deg),
            ("cl0", self.cl0),
            ("cl_slope1_per_deg", self.cl_slope1_per_deg),
            ("cl1", self.cl1),
            ("alpha_cl_max_deg", self.alpha_cl_max_deg),
            ("cdp", self.cdp),
            ("eff", self.eff),
            ("mass_kg", self.mass_kg),
            ("engine_power_w", self.engine_power_w),
            ("engine_rps", self.engine_rps),
            ("prop_diameter_m", self.prop_diameter_m),
            ("prop_a", self.prop_a),
            ("prop_b", self.prop_b),
        ]
    }

    /// Checks that the parameters can be flown: every field finite; mass, wing
    /// area, wing span, Oswald factor, propeller rev/s and diameter strictly
    /// positive (they divide); engine power, parasite drag and tail area not
    /// negative. Fields are checked in declaration order and the first problem
    /// is reported.
    ///
    /// # Errors
    /// [`AircraftError`] naming the first offending field.
    pub fn validate(&self) -> Result<(), AircraftError> {
        for (field, value) in self.fields() {
            if !value.is_finite() {
                return Err(AircraftError::NonFinite { field, value });
            }
            let positive = matches!(
                field,
                "wing_area_m2"
                    | "wing_span_m"
                    | "eff"
                    | "mass_kg"
                    | "engine_rps"
                    | "prop_diameter_m"
            );
            let non_negative = matches!(field, "tail_area_m2" | "cdp" | "engine_power_w");
            if positive && value <= 0.0 {
                return Err(AircraftError::NotPositive { field, value });
            }
            if non_negative && value < 0.0 {
                return Err(AircraftError::Negative { field, value });
            }
        }
        Ok(())
    }
}

impl Default for PalmerAircraft {
    /// [`PalmerAircraft::cessna_172`].
    fn default() -> Self {
        Self::cessna_172()
    }
}

/// Why a [`PalmerAircraft`] cannot be flown (see [`PalmerAircraft::validate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AircraftError {
    /// A parameter is NaN or infinite.
    NonFinite {
        /// Field name, as in [`PalmerAircraft`] (and its serialized form).
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be strictly positive is zero or negative.
    NotPositive {
        /// Field name, as in [`PalmerAircraft`] (and its serialized form).
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must not be negative is negative.
    Negative {
        /// Field name, as in [`PalmerAircraft`] (and its serialized form).
        field: &'static str,
        /// The offending value.
        value: f64,
    },
}

impl AircraftError {
    /// The name of the offending field.
    #[must_use]
    pub const fn field(&self) -> &'static str {
        match self {
            Self::NonFinite { field, .. }
            | Self::NotPositive { field, .. }
            | Self::Negative { field, .. } => field,
        }
    }
}

impl fmt::Display for AircraftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { field, value } => {
                write!(
                    f,
                    "aircraft parameter `{field}` must be finite, got {value}"
                )
            }
            Self::NotPositive { field, value } => {
                write!(
                    f,
                    "aircraft parameter `{field}` must be > 0, got {}",
                    ShortNumber(*value)
                )
            }
            Self::Negative { field, value } => {
                write!(
                    f,
                    "aircraft parameter `{field}` must be >= 0, got {}",
                    ShortNumber(*value)
                )
            }
        }
    }
}

impl core::error::Error for AircraftError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cessna_is_valid_and_default() {
        assert_eq!(PalmerAircraft::default(), PalmerAircraft::cessna_172());
        assert_eq!(PalmerAircraft::cessna_172().validate(), Ok(()));
    }

    #[test]
    fn serde_json_round_trip_is_exact() {
        let cessna = PalmerAircraft::cessna_172();
        let json = serde_json::to_string(&cessna).unwrap();
        assert!(json.contains("\"wing_area_m2\":16.2"), "{json}");
        assert!(json.contains("\"prop_b\":-1.32"), "{json}");
        let back: PalmerAircraft = serde_json::from_str(&json).unwrap();
        assert_eq!(back, cessna);
    }

    #[test]
    fn missing_field_is_a_deserialize_error() {
        let err = serde_json::from_str::<PalmerAircraft>(r#"{"wing_area_m2": 16.2}"#).unwrap_err();
        assert!(err.to_string().contains("missing field"), "{err}");
    }

    #[test]
    fn validate_names_the_first_bad_field() {
        let mut a = PalmerAircraft::cessna_172();
        a.mass_kg = 0.0;
        let err = a.validate().unwrap_err();
        assert_eq!(
            err,
            AircraftError::NotPositive {
                field: "mass_kg",
                value: 0.0
            }
        );
        assert_eq!(
            err.to_string(),
            "aircraft parameter `mass_kg` must be > 0, got 0"
        );

        let mut a = PalmerAircraft::cessna_172();
        a.prop_diameter_m = -1.0;
        a.cl0 = f64::NAN;
        let err = a.validate().unwrap_err();
        assert!(matches!(err, AircraftError::NonFinite { field: "cl0", .. }));

        let mut a = PalmerAircraft::cessna_172();
        a.engine_rps = f64::INFINITY;
        assert_eq!(a.validate().unwrap_err().field(), "engine_rps");

        let mut a = PalmerAircraft::cessna_172();
        a.cdp = -0.01;
        assert_eq!(
            a.validate(),
            Err(AircraftError::Negative {
                field: "cdp",
                value: -0.01
            })
        );

        // A glider (no engine) is fine.
        let mut a = PalmerAircraft::cessna_172();
        a.engine_power_w = 0.0;
        assert_eq!(a.validate(), Ok(()));
    }

    #[test]
    fn every_positive_field_is_checked() {
        for field in [
            "wing_area_m2",
            "wing_span_m",
            "eff",
            "mass_kg",
            "engine_rps",
            "prop_diameter_m",
        ] {
            let mut json = serde_json::to_value(PalmerAircraft::cessna_172()).unwrap();
            json[field] = serde_json::json!(-0.0);
            let a: PalmerAircraft = serde_json::from_value(json).unwrap();
            assert_eq!(a.validate().unwrap_err().field(), field);
        }
    }
}
