//! What a study needs of a model beyond flying it: the names of the controls
//! and physical parameters a study file can set, and cheap reads of a state.

use fdm_core::bourg::{Bourg, BourgAircraft, BourgControls, BourgState, MAX_THRUST_LB};
use fdm_core::message::ShortNumber;
use fdm_core::palmer::{
    Palmer, PalmerAircraft, PalmerControls, PalmerState, ALPHA_MAX_DEG, ALPHA_MIN_DEG,
    BANK_LIMIT_DEG,
};
use fdm_core::units::METRES_PER_FOOT;
use fdm_fleet::FleetKernel;
use fdm_run::RunModel;

/// A model a study can fly: a fleet model ([`FleetKernel`]) that runs can
/// also fly alone and record ([`RunModel`]), with the settings a study file
/// names.
pub trait StudyModel: FleetKernel + RunModel {
    /// The control settings a study file can give in `[controls]` or
    /// disperse as `controls.NAME`, with their units in the names.
    const CONTROL_KEYS: &'static [&'static str];
    /// The physical parameters a study file can give in `[aircraft]` or
    /// disperse as `aircraft.NAME`.
    const AIRCRAFT_KEYS: &'static [&'static str];

    /// Sets control `key` (one of [`Self::CONTROL_KEYS`]) to `value`.
    ///
    /// # Errors
    /// An unknown key or a value out of the control's range, in words.
    fn set_control(controls: &mut Self::Controls, key: &str, value: f64) -> Result<(), String>;

    /// The model's default aircraft with the parameters `values` (keys of
    /// [`Self::AIRCRAFT_KEYS`]) set, in order, then checked.
    ///
    /// # Errors
    /// An unknown key, or parameters the model cannot fly, in words.
    fn aircraft_with(values: &[(&str, f64)]) -> Result<Self::Aircraft, String>;

    /// Velocity in the earth frame, m/s: the view's `velocity_mps`, bit for bit.
    fn velocity_mps(state: &Self::State) -> [f64; 3];

    /// The state's clock, s.
    fn time_s(state: &Self::State) -> f64;
}

fn unknown(kind: &str, key: &str, keys: &[&str]) -> String {
    format!(
        "unknown {kind} `{key}`; expected one of {}",
        keys.join(", ")
    )
}

fn in_range(key: &str, value: f64, low: f64, high: f64) -> Result<f64, String> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err(format!(
            "{key} = {}: expected a number from {low} to {high}",
            ShortNumber(value)
        ))
    }
}

impl StudyModel for Palmer {
    const CONTROL_KEYS: &'static [&'static str] = &["throttle", "alpha_deg", "bank_deg"];
    const AIRCRAFT_KEYS: &'static [&'static str] = &[
        "wing_area_m2",
        "wing_span_m",
        "cl_slope0_per_deg",
        "cl0",
        "cl_slope1_per_deg",
        "cl1",
        "alpha_cl_max_deg",
        "cdp",
        "eff",
        "mass_kg",
        "engine_power_w",
        "engine_rps",
        "prop_diameter_m",
        "prop_a",
        "prop_b",
    ];

    fn set_control(controls: &mut PalmerControls, key: &str, value: f64) -> Result<(), String> {
        // The ranges of `sim-cli palmer --throttle/--alpha/--bank`.
        match key {
            "throttle" => controls.throttle = in_range(key, value, 0.0, 1.0)?,
            "alpha_deg" => {
                controls.alpha_deg = in_range(key, value, ALPHA_MIN_DEG, ALPHA_MAX_DEG)?;
            }
            "bank_deg" => {
                controls.bank_deg = in_range(key, value, -BANK_LIMIT_DEG, BANK_LIMIT_DEG)?;
            }
            _ => return Err(unknown("control", key, Self::CONTROL_KEYS)),
        }
        Ok(())
    }

    fn aircraft_with(values: &[(&str, f64)]) -> Result<PalmerAircraft, String> {
        let mut a = PalmerAircraft::cessna_172();
        for &(key, value) in values {
            let field = match key {
                "wing_area_m2" => &mut a.wing_area_m2,
                "wing_span_m" => &mut a.wing_span_m,
                "cl_slope0_per_deg" => &mut a.cl_slope0_per_deg,
                "cl0" => &mut a.cl0,
                "cl_slope1_per_deg" => &mut a.cl_slope1_per_deg,
                "cl1" => &mut a.cl1,
                "alpha_cl_max_deg" => &mut a.alpha_cl_max_deg,
                "cdp" => &mut a.cdp,
                "eff" => &mut a.eff,
                "mass_kg" => &mut a.mass_kg,
                "engine_power_w" => &mut a.engine_power_w,
                "engine_rps" => &mut a.engine_rps,
                "prop_diameter_m" => &mut a.prop_diameter_m,
                "prop_a" => &mut a.prop_a,
                "prop_b" => &mut a.prop_b,
                _ => return Err(unknown("aircraft parameter", key, Self::AIRCRAFT_KEYS)),
            };
            *field = value;
        }
        a.validate().map_err(|e| e.to_string())?;
        Ok(a)
    }

    fn velocity_mps(state: &PalmerState) -> [f64; 3] {
        state.velocity_mps.into()
    }

    fn time_s(state: &PalmerState) -> f64 {
        state.time_s
    }
}

impl StudyModel for Bourg {
    const CONTROL_KEYS: &'static [&'static str] = &["thrust_lb"];
    const AIRCRAFT_KEYS: &'static [&'static str] = &[
        "mass_scale",
        "area_scale",
        "max_thrust_lb",
        "delta_thrust_lb",
    ];

    fn set_control(controls: &mut BourgControls, key: &str, value: f64) -> Result<(), String> {
        match key {
            // The range of `sim-cli bourg --thrust-lb`; f32 as the model's.
            "thrust_lb" => {
                controls.thrust_lb = in_range(key, value, 0.0, f64::from(MAX_THRUST_LB))? as f32;
            }
            _ => return Err(unknown("control", key, Self::CONTROL_KEYS)),
        }
        Ok(())
    }

    fn aircraft_with(values: &[(&str, f64)]) -> Result<BourgAircraft, String> {
        let default = BourgAircraft::bourg_default();
        let mut airframe = *default.airframe();
        let mut max_thrust_lb = default.max_thrust_lb;
        let mut delta_thrust_lb = default.delta_thrust_lb;
        for &(key, value) in values {
            let scale = || in_range(key, value, 0.01, 100.0).map(|v| v as f32);
            match key {
                // Every element's mass times the factor: the mass properties
                // (total, centre of gravity, inertia) follow in `new`.
                "mass_scale" => {
                    let s = scale()?;
                    for e in &mut airframe.elements {
                        e.mass_slug *= s;
                    }
                }
                // Every element's area times the factor.
                "area_scale" => {
                    let s = scale()?;
                    for e in &mut airframe.elements {
                        e.area_ft2 *= s;
                    }
                }
                "max_thrust_lb" => max_thrust_lb = in_range(key, value, 0.0, 1e6)? as f32,
                "delta_thrust_lb" => delta_thrust_lb = in_range(key, value, 0.0, 1e6)? as f32,
                _ => return Err(unknown("aircraft parameter", key, Self::AIRCRAFT_KEYS)),
            }
        }
        let mut aircraft = BourgAircraft::new(airframe).map_err(|e| e.to_string())?;
        aircraft.max_thrust_lb = max_thrust_lb;
        aircraft.delta_thrust_lb = delta_thrust_lb;
        Ok(aircraft)
    }

    fn velocity_mps(state: &BourgState) -> [f64; 3] {
        state
            .velocity_ftps
            .map(f64::from)
            .scale(METRES_PER_FOOT)
            .into()
    }

    fn time_s(state: &BourgState) -> f64 {
        state.time_s
    }
}

/// Something to do with a study's model type.
pub(crate) trait StudyJob {
    type Output;
    fn call<M: StudyModel>(self) -> Self::Output;
}

/// Work done once with each model of the run library's registry, with its
/// type: what the study's model list of the registry is made of.
pub(crate) trait EachModel {
    /// Does the work with model `M`.
    fn model<M: StudyModel>(&mut self);
}

/// Calls `each` with the run library's registry's models
/// ([`fdm_run::model::MODELS`]: Palmer, Bourg), in its order. The one place
/// of this crate that names them.
pub(crate) fn registry_models(each: &mut impl EachModel) {
    each.model::<Palmer>();
    each.model::<Bourg>();
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::Model;

    /// The cheap reads are the view's fields, bit for bit (exact equality:
    /// they must be the same expressions).
    #[test]
    fn reads_match_the_view() {
        fn check<M: StudyModel>() {
            let (controls, state) = M::fleet_member(5);
            let aircraft = M::default_aircraft();
            let view = M::view(&aircraft, &controls, &state);
            assert_eq!(
                <M as fdm_fleet::LaneModel>::position_m(&state),
                view.position_m
            );
            assert_eq!(M::velocity_mps(&state), <[f64; 3]>::from(view.velocity_mps));
            assert_eq!(M::time_s(&state), view.time_s);
        }
        check::<Palmer>();
        check::<Bourg>();
    }

    #[test]
    fn parameters_are_set_and_checked() {
        let a = Palmer::aircraft_with(&[("mass_kg", 1000.0)]).unwrap();
        assert_eq!(a.mass_kg, 1000.0);
        assert!(Palmer::aircraft_with(&[("mass_kg", -1.0)]).is_err());
        assert!(Palmer::aircraft_with(&[("mass", 1.0)])
            .unwrap_err()
            .contains("mass_kg"));
        let b = Bourg::aircraft_with(&[("mass_scale", 1.1)]).unwrap();
        assert!(
            b.mass_properties().mass_slug
                > BourgAircraft::bourg_default().mass_properties().mass_slug
        );
        let mut c = Palmer::initial_controls();
        assert!(Palmer::set_control(&mut c, "throttle", 2.0).is_err());
        Palmer::set_control(&mut c, "throttle", 0.5).unwrap();
        assert_eq!(c.throttle, 0.5);
    }
}
