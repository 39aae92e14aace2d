//! Palmer's Cessna 172 in the run library: everything the registry needs of
//! it in one place. A recording keeps its aircraft as is ([`RunModel`]);
//! fleets fly it in `fdm_fleet::Fleet<Palmer>` and FlightGear draws the
//! c172p ([`FleetModel`]); the flight CSV's columns ([`CsvModel`]) and the
//! report's fields ([`ReportModel`], [`PalmerDetails`]).

use fdm_core::fingerprint;
use fdm_core::palmer::{Palmer, PalmerAircraft, PalmerControls, PalmerState};
use serde::{Deserialize, Serialize};

use crate::csv::CsvModel;
use crate::report::{Details, ReportModel};
use crate::{FleetModel, RunModel};

impl RunModel for Palmer {
    type AircraftRecord = PalmerAircraft;

    const ACMI_NAME: &'static str = "C172";
    const CALLSIGN: &'static str = "C172";
    #[cfg(feature = "dis")]
    const DIS_KIND: fdm_dis::AircraftKind = fdm_dis::AircraftKind::Cessna172;
    const FG_AIRCRAFT: &'static str = "c172p";
    /// The c172p's Nasal `engine.nas` pops up "Out of fuel!" whenever the engine
    /// runs while its selected tanks (0 and 1 without JSBSim) hold 0 gallons, which
    /// they do with `--fdm=null`: give them fuel (nothing consumes it). FlightGear
    /// 2020.3 clamps a tank's level to its capacity and weighs it by its density,
    /// both 0 without JSBSim, so capacity (28 US gallons) and density (6 lb per
    /// gallon, avgas) go first. A timer looks every 2 s, because the c172p's own
    /// start-up scripts reset the tanks after the FDM is initialised. Measured
    /// live: `--prop:` options for the levels read back 0.
    const FG_STARTUP_NASAL: &'static str = "var refuel = func { foreach (var tank; [0, 1]) { \
        var path = \"/consumables/fuel/tank[\" ~ tank ~ \"]/\"; \
        if (getprop(path ~ \"level-gal_us\") < 1) { setprop(path ~ \"capacity-gal_us\", 28); \
        setprop(path ~ \"density-ppg\", 6); setprop(path ~ \"level-gal_us\", 20); } } \
        settimer(refuel, 2); }; refuel();";

    fn aircraft_record(aircraft: &PalmerAircraft) -> PalmerAircraft {
        *aircraft
    }

    fn aircraft_from_record(record: PalmerAircraft) -> Result<PalmerAircraft, String> {
        record.validate().map_err(|e| e.to_string())?;
        Ok(record)
    }

    fn state_fingerprint(state: &PalmerState) -> u64 {
        fingerprint::palmer_state(state)
    }
}

impl FleetModel for Palmer {
    type Lanes = fdm_fleet::Fleet<Self>;

    const FG_MP_MODEL: &'static str = "Aircraft/c172p/Models/c172p.xml";

    fn offset_state(state: &PalmerState, north_m: f64, west_m: f64, up_m: f64) -> PalmerState {
        let mut moved = *state;
        moved.position_m.x += north_m;
        moved.position_m.y += west_m;
        moved.position_m.z += up_m;
        moved
    }

    /// The attitude matrix straight from the velocity and controls, without
    /// the Euler angles ([`crate::dis::palmer_rough`]).
    #[cfg(feature = "dis")]
    fn dis_rough(first: usize, states: &[Option<PalmerState>], out: &mut [Option<fdm_dis::Rough>]) {
        crate::dis::palmer_rough(first, states, out);
    }
}

impl CsvModel for Palmer {
    const CSV_SPEED_COLUMN: &'static str = "airspeed";
    const METRES_PER_UNIT: f64 = 1.0;
    const CSV_COLUMNS: &'static [&'static str] = &[
        "airspeed",
        "throttle",
        "alpha_deg",
        "bank_deg",
        "flaps_deg",
        "climb_angle_deg",
        "climb_rate",
        "heading_deg",
    ];

    fn native_position(state: &PalmerState) -> [f64; 3] {
        state.position_m.into()
    }

    fn native_velocity(state: &PalmerState) -> [f64; 3] {
        state.velocity_mps.into()
    }

    fn csv_values(controls: &PalmerControls, state: &PalmerState, out: &mut Vec<f64>) {
        out.extend_from_slice(&[
            state.airspeed_mps(),
            controls.throttle,
            controls.alpha_deg,
            controls.bank_deg,
            controls.flaps.degrees(),
            state.climb_angle_deg(),
            state.climb_rate_mps(),
            state.heading_deg(),
        ]);
    }
}

impl ReportModel for Palmer {
    type Details = PalmerDetails;

    fn details(
        _aircraft: &PalmerAircraft,
        controls: &PalmerControls,
        state: &PalmerState,
    ) -> PalmerDetails {
        PalmerDetails {
            airspeed: state.airspeed_mps(),
            controls: PalmerControlsReport {
                throttle: controls.throttle,
                alpha_deg: controls.alpha_deg,
                bank_deg: controls.bank_deg,
                flaps_deg: controls.flaps.degrees(),
                brakes: controls.brakes,
            },
            climb_angle_deg: state.climb_angle_deg(),
            climb_rate: state.climb_rate_mps(),
            heading_deg: state.heading_deg(),
        }
    }
}

/// Palmer's controls as the model holds them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerControlsReport {
    /// Throttle fraction, 0..1.
    pub throttle: f64,
    /// Angle of attack, degrees.
    pub alpha_deg: f64,
    /// Bank, degrees, positive right.
    pub bank_deg: f64,
    /// Flap setting, degrees (0, 20 or 40).
    pub flaps_deg: f64,
    /// Wheel brakes set (our extension); absent from the JSON while off, so
    /// reports without the brakes read as before.
    #[serde(default, skip_serializing_if = "is_off")]
    pub brakes: bool,
}

/// Serde's test for leaving `brakes` out of a report: brakes off.
#[allow(clippy::trivially_copy_pass_by_ref)] // serde passes a reference
fn is_off(brakes: &bool) -> bool {
    !*brakes
}

/// What the summary and the HUD add while the brakes are set.
#[must_use]
pub fn brakes_note(brakes: bool) -> &'static str {
    if brakes {
        "  BRAKES"
    } else {
        ""
    }
}

/// Palmer-only report fields (all `f64` in the model).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PalmerDetails {
    /// Airspeed, m/s.
    pub airspeed: f64,
    /// Current controls.
    pub controls: PalmerControlsReport,
    /// Climb angle, degrees.
    pub climb_angle_deg: f64,
    /// Climb rate (vz), m/s.
    pub climb_rate: f64,
    /// The model's heading angle, degrees in [0, 360), measured from +x toward +y
    /// (i.e. toward the west; not a compass heading, see `attitude_deg.heading`).
    pub heading_deg: f64,
}

impl Details for PalmerDetails {
    const MODEL: &'static str = "palmer";
    const POSITION_UNIT: &'static str = "m";
    fn summary(&self) -> String {
        format!(
            "airspeed  {:.3} m/s  climb {:.2} deg, {:.3} m/s\n\
             controls  throttle {:.0} %  alpha {} deg  bank {} deg  flaps {} deg{}",
            self.airspeed,
            self.climb_angle_deg,
            self.climb_rate,
            self.controls.throttle * 100.0,
            self.controls.alpha_deg,
            self.controls.bank_deg,
            self.controls.flaps_deg,
            brakes_note(self.controls.brakes),
        )
    }
}
