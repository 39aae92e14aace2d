//! A third model flown from `sim-cli` (cargo feature `glider`): the
//! point-mass glider of `fdm-ecs/examples/third_model.rs` (its model is
//! [`model`], one source for the example and the CLI), with everything the
//! run library and the CLI need of it in this one module, and one line in
//! the registry ([`crate::models`]). Nothing else in the workspace names it.
//!
//! `sim-cli glider` flies it with every option both models share (headless
//! or interactive, scripts, `--csv`, `--record` and `replay`, `--acmi`,
//! `--plot`, `--fg`, `--dis`); `fleet --model glider`, `fgfs-command glider`
//! and studies of `model = "glider"` too. FlightGear shows it as the UFO.
//! `sim-cli-tests`' `cli_glider` flies it end to end.

use fdm_core::fingerprint::Hasher;
use fdm_core::model::Model;
use fdm_run::model::pilot::{
    tenths, ControlsLine, Key, KeyBindings, NumberRange, OptionValue, PilotModel, RangeNote,
    StartOption,
};
use fdm_run::report::{Details as ReportDetails, ReportModel};
use fdm_run::NamedInputs;
use fdm_run::{csv::CsvModel, FleetModel, RunModel};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

mod model;
pub use model::*;

impl RunModel for Glider {
    type AircraftRecord = GliderAircraft;

    const ACMI_NAME: &'static str = "Glider";
    const CALLSIGN: &'static str = "GLD";
    const FG_AIRCRAFT: &'static str = "ufo";
    /// As Bourg's: the UFO draws itself with `--fdm=null` only when told to.
    const FG_OPTIONS: &'static [&'static str] = &["--prop:bool:/sim/model/always-show-in-MP=true"];

    fn aircraft_record(aircraft: &GliderAircraft) -> GliderAircraft {
        aircraft.clone()
    }

    fn aircraft_from_record(record: GliderAircraft) -> Result<GliderAircraft, String> {
        validate(&record)?;
        Ok(record)
    }

    fn state_fingerprint(state: &GliderState) -> u64 {
        let mut h = Hasher::new().bytes(b"glider").f64(state.time_s);
        for v in state.position_m.iter().chain(state.velocity_mps.iter()) {
            h = h.f64(*v);
        }
        h.finish()
    }
}

/// Every parameter finite and positive.
fn validate(a: &GliderAircraft) -> Result<(), String> {
    for (name, value) in [
        ("mass_kg", a.mass_kg),
        ("wing_area_m2", a.wing_area_m2),
        ("cd0", a.cd0),
        ("induced_k", a.induced_k),
        ("air_density_kgpm3", a.air_density_kgpm3),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(format!("{name} {value} is not a finite number > 0"));
        }
    }
    Ok(())
}

impl FleetModel for Glider {
    type Lanes = fdm_fleet::Fleet<Self>;

    const FG_MP_MODEL: &'static str = "Aircraft/ufo/Models/ufo.xml";

    fn offset_state(state: &GliderState, north_m: f64, west_m: f64, up_m: f64) -> GliderState {
        let mut moved = *state;
        moved.position_m += Vector3::new(north_m, west_m, up_m);
        moved
    }
}

impl CsvModel for Glider {
    const CSV_COLUMNS: &'static [&'static str] = &["airspeed", "lift_coefficient", "bank_deg"];
    const CSV_SPEED_COLUMN: &'static str = "airspeed";
    const METRES_PER_UNIT: f64 = 1.0;

    fn native_position(state: &GliderState) -> [f64; 3] {
        state.position_m.into()
    }

    fn native_velocity(state: &GliderState) -> [f64; 3] {
        state.velocity_mps.into()
    }

    fn csv_values(controls: &GliderControls, state: &GliderState, out: &mut Vec<f64>) {
        out.extend([
            state.velocity_mps.norm(),
            controls.lift_coefficient,
            controls.bank_deg,
        ]);
    }
}

/// The glider's report fields.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GliderDetails {
    /// Airspeed, m/s.
    pub airspeed: f64,
    /// Lift coefficient.
    pub lift_coefficient: f64,
    /// Bank, degrees, right positive.
    pub bank_deg: f64,
}

impl ReportDetails for GliderDetails {
    const MODEL: &'static str = Glider::NAME;
    const POSITION_UNIT: &'static str = "m";

    fn summary(&self) -> String {
        format!(
            "airspeed  {:.3} m/s  lift coefficient {}  bank {} deg",
            self.airspeed, self.lift_coefficient, self.bank_deg
        )
    }
}

impl ControlsLine for GliderDetails {
    fn controls_line(&self) -> String {
        format!(
            "CL {:4.2}   BANK {:+5.1} deg",
            self.lift_coefficient,
            tenths(self.bank_deg)
        )
    }
}

impl ReportModel for Glider {
    type Details = GliderDetails;

    fn details(_: &GliderAircraft, c: &GliderControls, s: &GliderState) -> GliderDetails {
        GliderDetails {
            airspeed: s.velocity_mps.norm(),
            lift_coefficient: c.lift_coefficient,
            bank_deg: c.bank_deg,
        }
    }
}

impl NamedInputs for Glider {
    const CONTROL_KEYS: &'static [&'static str] = &["lift_coefficient", "bank_deg"];
    const AIRCRAFT_KEYS: &'static [&'static str] = &[
        "mass_kg",
        "wing_area_m2",
        "cd0",
        "induced_k",
        "air_density_kgpm3",
    ];

    fn set_control(c: &mut GliderControls, key: &str, value: f64) -> Result<(), String> {
        let (field, low, high) = match key {
            "lift_coefficient" => (&mut c.lift_coefficient, 0.0, MAX_CL),
            "bank_deg" => (&mut c.bank_deg, -MAX_BANK_DEG, MAX_BANK_DEG),
            _ => return Err(format!("unknown control `{key}`")),
        };
        if !(value.is_finite() && (low..=high).contains(&value)) {
            return Err(format!(
                "{key} = {value}: expected a number from {low} to {high}"
            ));
        }
        *field = value;
        Ok(())
    }

    fn aircraft_with(values: &[(&str, f64)]) -> Result<GliderAircraft, String> {
        let mut a = Self::default_aircraft();
        for &(key, value) in values {
            *match key {
                "mass_kg" => &mut a.mass_kg,
                "wing_area_m2" => &mut a.wing_area_m2,
                "cd0" => &mut a.cd0,
                "induced_k" => &mut a.induced_k,
                "air_density_kgpm3" => &mut a.air_density_kgpm3,
                _ => return Err(format!("unknown aircraft parameter `{key}`")),
            } = value;
        }
        validate(&a)?;
        Ok(a)
    }

    fn velocity_mps(state: &GliderState) -> [f64; 3] {
        state.velocity_mps.into()
    }

    fn time_s(state: &GliderState) -> f64 {
        state.time_s
    }
}

/// The lift coefficient's range, 0 to this (the model's clamp).
const MAX_CL: f64 = 1.4;
/// The bank's range, ± this, degrees (the model's clamp).
const MAX_BANK_DEG: f64 = 45.0;

impl KeyBindings for GliderAction {
    const KEYS: &'static [(Key, Self)] = &[
        (Key::Down, Self::PitchUp),
        (Key::Up, Self::PitchDown),
        (Key::Left, Self::BankLeft),
        (Key::Right, Self::BankRight),
    ];
    const KEY_HELP: &'static str = "Down/Up pitch up/down  Left/Right bank";
}

/// `sim-cli glider`'s own option (after the options every model shares):
/// `--lift-coefficient`, 0 to [`MAX_CL`].
impl PilotModel for Glider {
    const AIRCRAFT: &'static str = "a point-mass glider";
    const ABOUT: &'static str =
        "Fly a point-mass glider (the third model: semi-implicit Euler, f64; metres, m/s)";
    const START_OPTIONS: &'static [StartOption] = &[StartOption::number(
        "lift-coefficient",
        "CL",
        "Lift coefficient at frame 0 (0..1.4) [default: 0.6, the model's start]",
        NumberRange {
            low: 0.0,
            high: MAX_CL,
            note: RangeNote::What("a lift coefficient"),
        },
        None,
    )];

    /// The model's start, with `--lift-coefficient`.
    fn start_controls(values: &[OptionValue]) -> Result<GliderControls, String> {
        let mut controls = Glider::initial_controls();
        match *values {
            [OptionValue::Absent] => {}
            [OptionValue::Number(cl)] => controls.lift_coefficient = cl,
            _ => return Err(fdm_run::model::pilot::unexpected_values(values)),
        }
        Ok(controls)
    }
}
