//! Bourg's 6-DoF aircraft in the run library: everything the registry
//! needs of it in one place. A recording keeps its airframe and thrust
//! limits ([`BourgAircraftRecord`], [`RunModel`]); fleets fly it in
//! `fdm_fleet::Fleet<Bourg>` and FlightGear draws the UFO ([`FleetModel`]);
//! the flight CSV's columns ([`CsvModel`]) and the report's fields
//! ([`ReportModel`], [`BourgDetails`]); the controls and parameters a study
//! file sets by name ([`NamedInputs`]).

use fdm_core::bourg::{Airframe, Bourg, BourgAircraft, BourgControls, BourgState};
use fdm_core::fingerprint;
use fdm_core::model::FlightStatus;
use serde::{Deserialize, Serialize};

use crate::csv::CsvModel;
use crate::model::{in_range, not_one_of, unknown_key, NamedInputs};
use crate::report::{CommonState, Details, ReportModel, Snapshot};
use crate::{FleetModel, RunModel};
use fdm_core::bourg::MAX_THRUST_LB;
use fdm_core::units::METRES_PER_FOOT;

/// Bourg's aircraft as a recording stores it: the airframe (from which
/// [`BourgAircraft::new`] derives the mass properties) and the thrust limits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgAircraftRecord {
    /// The eight lifting elements.
    pub airframe: Airframe,
    /// Maximum thrust, lb.
    pub max_thrust_lb: f32,
    /// Thrust change per thrust-up/down action, lb.
    pub delta_thrust_lb: f32,
}

impl RunModel for Bourg {
    type AircraftRecord = BourgAircraftRecord;

    const ACMI_NAME: &'static str = "Bourg 6-DoF";
    const CALLSIGN: &'static str = "BRG";
    #[cfg(feature = "dis")]
    const DIS_KIND: fdm_dis::AircraftKind = fdm_dis::AircraftKind::SMALL_CIVIL_FIXED_WING;
    /// The thesis showed Bourg's aircraft as the UFO.
    const FG_AIRCRAFT: &'static str = "ufo";
    /// The UFO's `Models/ufo.xml` draws the model only when `/sim/flight-model` is
    /// `ufo` or `/sim/model/always-show-in-MP` is true; with `--fdm=null` the first
    /// is false, so set the second.
    const FG_OPTIONS: &'static [&'static str] = &["--prop:bool:/sim/model/always-show-in-MP=true"];

    fn aircraft_record(aircraft: &BourgAircraft) -> BourgAircraftRecord {
        BourgAircraftRecord {
            airframe: *aircraft.airframe(),
            max_thrust_lb: aircraft.max_thrust_lb,
            delta_thrust_lb: aircraft.delta_thrust_lb,
        }
    }

    fn aircraft_from_record(record: BourgAircraftRecord) -> Result<BourgAircraft, String> {
        let mut aircraft = BourgAircraft::new(record.airframe).map_err(|e| e.to_string())?;
        for (name, value) in [
            ("max_thrust_lb", record.max_thrust_lb),
            ("delta_thrust_lb", record.delta_thrust_lb),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(format!("{name} {value} is not a finite thrust >= 0"));
            }
        }
        aircraft.max_thrust_lb = record.max_thrust_lb;
        aircraft.delta_thrust_lb = record.delta_thrust_lb;
        Ok(aircraft)
    }

    fn state_fingerprint(state: &BourgState) -> u64 {
        fingerprint::bourg_state(state)
    }
}

impl FleetModel for Bourg {
    type Lanes = fdm_fleet::Fleet<Self>;

    const FG_MP_MODEL: &'static str = "Aircraft/ufo/Models/ufo.xml";

    /// Bourg's position is in feet, `f32`: the offset is converted and rounded once.
    fn offset_state(state: &BourgState, north_m: f64, west_m: f64, up_m: f64) -> BourgState {
        let ft = |m: f64| (m / fdm_core::units::METRES_PER_FOOT) as f32;
        let mut moved = *state;
        moved.position_ft.x += ft(north_m);
        moved.position_ft.y += ft(west_m);
        moved.position_ft.z += ft(up_m);
        moved
    }

    /// The view's frame without the rest of the view, its attitude matrix
    /// through the model's `f32` Euler angles as the view's
    /// ([`bourg_rough`]).
    #[cfg(feature = "dis")]
    fn dis_rough(_first: usize, states: &[Option<BourgState>], out: &mut [Option<fdm_dis::Rough>]) {
        bourg_rough(states, out);
    }

    /// [`bourg_rough_lanes`]: the same frames, the Euler angles' `atan2`s
    /// eight at a time.
    #[cfg(feature = "dis")]
    #[inline(always)]
    fn dis_rough_lanes(
        _first: usize,
        states: &[Option<BourgState>],
        out: &mut fdm_dis::RoughLanes,
    ) {
        bourg_rough_lanes(states, out);
    }
}

/// [`FleetModel::dis_rough`] for Bourg: each aircraft's view's time,
/// position and velocity (feet widened to `f64`, times
/// [`METRES_PER_FOOT`], the view's
/// operations) and the view's own attitude matrix, bit for bit, without the
/// rest of the view (the body velocity, alpha, sideslip, airspeed).
///
/// The matrix is not made from the quaternion alone: the exact path's
/// attitude goes through the model's `f32` Euler angles
/// ([`BourgState::euler_angles_deg`],
/// `f32` products, an `asin` of a quaternion not quite of unit length, a
/// gimbal-lock branch, angles rounded to `f32` radians and again to `f32`
/// degrees), which move its matrix from the quaternion's by far more than
/// [`fdm_dis::ROUGH_TOLERANCE`] (up to 1.4e-3 over the states of the test
/// `bourg_rough_is_the_views_frame`, which asserts it is more than ten
/// times the tolerance). So the angles are the model's and the matrix is
/// [`fdm_core::geodesy::bourg_attitude`]'s `body_to_ned`, the exact path's
/// operations: within 0 of it, gimbal lock included. What the screen saves
/// for Bourg is the placement in ECEF and the dead-reckoning comparison of
/// the aircraft it clears. A state with a non-finite number gets no rough
/// frame (the exact path takes it).
#[cfg(feature = "dis")]
pub fn bourg_rough(states: &[Option<BourgState>], out: &mut [Option<fdm_dis::Rough>]) {
    use fdm_core::units::METRES_PER_FOOT;
    let widen = |v: nalgebra::Vector3<f32>| v.map(f64::from);
    for (s, o) in states.iter().zip(out.iter_mut()) {
        *o = s.filter(BourgState::is_finite).and_then(|s| {
            let body_to_ned = fdm_core::geodesy::bourg_attitude(s.euler_angles_deg()).body_to_ned();
            body_to_ned
                .iter()
                .all(|e| e.is_finite())
                .then(|| fdm_dis::Rough {
                    time_s: s.time_s,
                    position_m: widen(s.position_ft) * METRES_PER_FOOT,
                    velocity_mps: widen(s.velocity_ftps) * METRES_PER_FOOT,
                    body_to_ned,
                })
        });
    }
}

/// [`bourg_rough`] for up to [`fdm_dis::ROUGH_LANES`] aircraft, into
/// `out`'s lanes (`ok[k]` false where [`bourg_rough`] makes none), bit for
/// bit (the test `bourg_rough_lanes_is_bourg_rough`): the Euler angles of
/// all the lanes at once ([`fdm_core::bourg::ops::euler_deg_from_quat_lanes`],
/// bit for bit [`BourgState::euler_angles_deg`], its two `atan2` eight at a
/// time), then each lane's matrix as [`bourg_rough`] makes it. Always
/// inlined, so that the fleet screen's instruction set compiles it too.
#[cfg(feature = "dis")]
#[inline(always)]
pub fn bourg_rough_lanes(states: &[Option<BourgState>], out: &mut fdm_dis::RoughLanes) {
    use fdm_core::units::METRES_PER_FOOT;
    const L: usize = fdm_dis::ROUGH_LANES;
    let mut finite = [false; L];
    // Lanes without a finite state get the identity (never read).
    let mut q = [fdm_core::bourg::Quaternion::new(1.0, 0.0, 0.0, 0.0); L];
    for (k, s) in states.iter().take(L).enumerate() {
        if let Some(s) = s.filter(BourgState::is_finite) {
            finite[k] = true;
            q[k] = s.orientation;
            out.time_s[k] = s.time_s;
            for c in 0..3 {
                out.position_m[c][k] = f64::from(s.position_ft[c]) * METRES_PER_FOOT;
                out.velocity_mps[c][k] = f64::from(s.velocity_ftps[c]) * METRES_PER_FOOT;
            }
        }
    }
    let euler = fdm_core::bourg::ops::euler_deg_from_quat_lanes(&q);
    for (k, e) in euler.iter().enumerate() {
        out.ok[k] = false;
        if finite[k] {
            let m = fdm_core::geodesy::bourg_attitude(*e).body_to_ned();
            if m.iter().all(|x| x.is_finite()) {
                out.ok[k] = true;
                for (i, b) in out.body_to_ned.iter_mut().enumerate() {
                    b[k] = m[(i / 3, i % 3)];
                }
            }
        }
    }
}

impl CsvModel for Bourg {
    const CSV_SPEED_COLUMN: &'static str = "speed";
    const METRES_PER_UNIT: f64 = fdm_core::units::METRES_PER_FOOT;
    /// `flaps` and `stalling` are written as 0 or 1.
    const CSV_COLUMNS: &'static [&'static str] = &[
        "speed",
        "euler_x_deg",
        "euler_y_deg",
        "euler_z_deg",
        "thrust_lb",
        "flaps",
        "stalling",
        "pitch_trim",
    ];

    fn native_position(state: &BourgState) -> [f64; 3] {
        state.position_ft.map(f64::from).into()
    }

    fn native_velocity(state: &BourgState) -> [f64; 3] {
        state.velocity_ftps.map(f64::from).into()
    }

    fn csv_values(controls: &BourgControls, state: &BourgState, out: &mut Vec<f64>) {
        let euler = state.euler_angles_deg();
        out.extend_from_slice(&[
            f64::from(state.speed_ftps()),
            f64::from(euler.x),
            f64::from(euler.y),
            f64::from(euler.z),
            f64::from(controls.thrust_lb),
            f64::from(u8::from(controls.landing_flaps)),
            f64::from(u8::from(state.stalling)),
            f64::from(controls.pitch_trim),
        ]);
    }
}

impl ReportModel for Bourg {
    type Details = BourgDetails;

    fn details(
        _aircraft: &BourgAircraft,
        controls: &BourgControls,
        state: &BourgState,
    ) -> BourgDetails {
        BourgDetails {
            speed: f64::from(state.speed_ftps()),
            euler_deg: state.euler_angles_deg().map(f64::from).into(),
            thrust_lb: f64::from(controls.thrust_lb),
            flaps: controls.landing_flaps,
            stalling: state.stalling,
            pitch_trim: f64::from(controls.pitch_trim),
        }
    }
}

/// Bourg-only report fields. The model is `f32`; every float here is the
/// model's `f32` widened exactly with `f64::from`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgDetails {
    /// Speed |velocity|, ft/s.
    pub speed: f64,
    /// Euler angles [x roll, y pitch (positive nose-down), z yaw] in degrees, exactly as
    /// `MakeEulerAnglesFromQ` computes them.
    pub euler_deg: [f64; 3],
    /// Thrust, lb.
    pub thrust_lb: f64,
    /// Landing flaps down.
    pub flaps: bool,
    /// Any wing element past its stall angle on the last step.
    pub stalling: bool,
    /// The persistent pitch trim, −1..=1 (an extension of the model; 0
    /// unless trimmed or moved with T/G). Absent in older reports.
    #[serde(default)]
    pub pitch_trim: f64,
}

impl BourgDetails {
    /// A fixed snapshot (the same in every call) of Bourg's aircraft at
    /// 183.12346 ft/s (an `f32`), 3000 lb of thrust, flaps down, on
    /// [`CommonState::sample`](crate::report::CommonState::sample): for
    /// tests and examples of code that shows a snapshot. Its Euler angles
    /// are that common state's attitude (roll 5°, pitch 2.5° nose-up,
    /// heading 359.5°) in the model's axes, as
    /// [`fdm_core::geodesy::bourg_attitude`] reads them: `[5, -2.5, 0.5]`.
    #[must_use]
    pub fn sample_snapshot() -> Snapshot<Self> {
        Snapshot {
            common: CommonState::sample(),
            details: Self {
                speed: f64::from(183.123_46_f32),
                euler_deg: [5.0_f32, -2.5, 0.5].map(f64::from),
                thrust_lb: 3000.0,
                flaps: true,
                stalling: false,
                pitch_trim: 0.0,
            },
            status: FlightStatus::Airborne,
            stalling: false,
            airspeed_mps: f64::from(183.123_46_f32) * 0.3048,
        }
    }
}

impl Details for BourgDetails {
    const MODEL: &'static str = "bourg";
    const POSITION_UNIT: &'static str = "ft";
    /// `flaps` and `stalling` are written as 0 or 1.
    fn summary(&self) -> String {
        format!(
            "speed     {:.3} ft/s  thrust {} lb  flaps {}  stalling {}  pitch trim {:.3}",
            self.speed,
            self.thrust_lb,
            if self.flaps { "down" } else { "up" },
            if self.stalling { "yes" } else { "no" },
            self.pitch_trim,
        )
    }
}

/// What a study file can set of the model by name, and its cheap reads.
impl NamedInputs for Bourg {
    const CONTROL_KEYS: &'static [&'static str] = &["thrust_lb", "landing_flaps", "pitch_trim"];
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
            // Down or up, 1 or 0, as the column `landing_flaps` of the
            // controls (`CONTROL_FIELDS`); `sim-cli bourg` has no start
            // option for it (keys K/L).
            "landing_flaps" => {
                controls.landing_flaps = [false, true]
                    .into_iter()
                    .find(|&down| f64::from(u8::from(down)) == value)
                    .ok_or_else(|| not_one_of(key, value, "0 or 1"))?;
            }
            // The controls' documented −1..=1 (`sim-cli bourg` has no start
            // option for it: keys T/G); f32 as the model's.
            "pitch_trim" => controls.pitch_trim = in_range(key, value, -1.0, 1.0)? as f32,
            _ => return Err(unknown_key("control", key, Self::CONTROL_KEYS)),
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
                _ => return Err(unknown_key("aircraft parameter", key, Self::AIRCRAFT_KEYS)),
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

// --- Flown by hand from a front end (`sim-cli bourg`): start options, keys, HUD line.

use crate::model::pilot::{
    ControlsLine, Key, KeyBindings, NumberRange, OptionValue, PilotModel, RangeNote, StartOption,
};
use fdm_core::bourg::BourgAction;
use fdm_core::model::Model;

/// `--thrust-lb`: pounds in 0..[`MAX_THRUST_LB`], Bourg's thrust range; not
/// with `--trim`, which sets the thrust itself.
impl PilotModel for Bourg {
    const AIRCRAFT: &'static str = "Bourg's 6-DoF aircraft";
    const ABOUT: &'static str =
        "Fly David Bourg's 6-DoF aircraft (rigid body, Euler, f32; feet, ft/s, lb)";
    const START_OPTIONS: &'static [StartOption] = &[StartOption::number(
        "thrust-lb",
        "LB",
        "Thrust at frame 0, lb (0..3000) [default: 500, the model's start]",
        NumberRange {
            low: 0.0,
            high: MAX_THRUST_LB as f64,
            note: RangeNote::Unit(" lb"),
        },
        None,
    )
    .conflicting(&["trim"])];

    /// The model's start, with `--thrust-lb`.
    fn start_controls(values: &[OptionValue]) -> Result<BourgControls, String> {
        let mut controls = Bourg::initial_controls();
        match values {
            [OptionValue::Absent] => {}
            // In 0..3000 (checked by its range): exact enough in f32 for any typed value.
            #[allow(clippy::cast_possible_truncation)]
            &[OptionValue::Number(thrust_lb)] => controls.thrust_lb = thrust_lb as f32,
            _ => return Err(crate::model::pilot::unexpected_values(values)),
        }
        Ok(controls)
    }
}

impl KeyBindings for BourgAction {
    const KEYS: &'static [(Key, Self)] = &[
        (Key::Char('e'), Self::ThrustUp),
        (Key::Char('d'), Self::ThrustDown),
        (Key::Down, Self::PitchUp),
        (Key::Up, Self::PitchDown),
        (Key::Left, Self::RollLeft),
        (Key::Right, Self::RollRight),
        (Key::Char('n'), Self::YawLeft),
        (Key::Char('m'), Self::YawRight),
        (Key::Char('k'), Self::FlapsDown),
        (Key::Char('l'), Self::FlapsUp),
        (Key::Char('t'), Self::TrimNoseUp),
        (Key::Char('g'), Self::TrimNoseDown),
    ];
    const KEY_HELP: &'static str =
        "E/D thrust  Down/Up pitch up/down  T/G trim nose up/down  Left/Right roll  N/M yaw  K/L flaps down/up";
}

impl ControlsLine for BourgDetails {
    fn controls_line(&self) -> String {
        format!(
            "THRUST {:4.0} lb   FLAPS {}   TRIM {:+.2}",
            self.thrust_lb,
            if self.flaps { "down" } else { "up" },
            self.pitch_trim
        )
    }
}

// --- Named columns and the agent's tasks (`ColumnModel`, `AgentModel`: the
// Python bindings' state and control columns and Gymnasium tasks).

use super::agent::{AgentModel, Kinematics, LaneAgent, MAX_CONTROL_OBS};
use super::columns::{ColumnModel, ControlRange, MAX_BLOCK_FIELDS};
use fdm_core::bourg::Flap;
use fdm_core::bourg::{BourgLanes, LANES};
use fdm_core::real::kernel::Block;

/// A Bourg surface as a number: −1, 0 or +1.
#[inline]
fn flap_code(f: Flap) -> f64 {
    match f {
        Flap::TrailingEdgeDown => -1.0,
        Flap::Neutral => 0.0,
        Flap::TrailingEdgeUp => 1.0,
    }
}

/// The surface position of a number: −1, 0 or +1, else a message.
#[inline]
fn flap_from(value: f64) -> Result<Flap, String> {
    match value {
        -1.0 => Ok(Flap::TrailingEdgeDown),
        0.0 => Ok(Flap::Neutral),
        1.0 => Ok(Flap::TrailingEdgeUp),
        v => Err(format!("{v} is not -1, 0 or 1")),
    }
}

impl ColumnModel for Bourg {
    const STATE_FIELDS: &'static [&'static str] = &[
        "time_s",
        "x_ft",
        "y_ft",
        "z_ft",
        "vx_ftps",
        "vy_ftps",
        "vz_ftps",
        "u_ftps",
        "v_ftps",
        "w_ftps",
        "p_radps",
        "q_radps",
        "r_radps",
        "qw",
        "qx",
        "qy",
        "qz",
        "stalling",
        "speed_ftps",
        "euler_x_deg",
        "euler_y_deg",
        "euler_z_deg",
    ];
    // Surfaces: +1 is the action's direction (`elevator` +1 = pitch-up,
    // `aileron` +1 = roll-right, `rudder` +1 = yaw-right).
    const CONTROL_FIELDS: &'static [ControlRange] = &[
        ("thrust_lb", 0.0, MAX_THRUST_LB as f64),
        ("elevator", -1.0, 1.0),
        ("aileron", -1.0, 1.0),
        ("rudder", -1.0, 1.0),
        ("landing_flaps", 0.0, 1.0),
        ("pitch_trim", -1.0, 1.0),
    ];

    const TRIM_SETS: &'static [(&'static str, &'static str)] = &[("thrust_lb", "the thrust")];

    #[inline]
    fn state_values(s: &BourgState, out: &mut [f64]) {
        // The state's own fields, then the four derived ones (speed, Euler angles).
        Self::state_values_head(s, out);
        let e = s.euler_angles_deg();
        let w = f64::from;
        out[18..].copy_from_slice(&[w(s.speed_ftps()), w(e.x), w(e.y), w(e.z)]);
    }

    const BLOCK_FIELDS: usize = 4;

    #[inline(always)]
    fn state_values_head(s: &BourgState, out: &mut [f64]) {
        let w = f64::from;
        out[..18].copy_from_slice(&[
            s.time_s,
            w(s.position_ft.x),
            w(s.position_ft.y),
            w(s.position_ft.z),
            w(s.velocity_ftps.x),
            w(s.velocity_ftps.y),
            w(s.velocity_ftps.z),
            w(s.velocity_body_ftps.x),
            w(s.velocity_body_ftps.y),
            w(s.velocity_body_ftps.z),
            w(s.angular_velocity_radps.x),
            w(s.angular_velocity_radps.y),
            w(s.angular_velocity_radps.z),
            w(s.orientation.w),
            w(s.orientation.i),
            w(s.orientation.j),
            w(s.orientation.k),
            if s.stalling { 1.0 } else { 0.0 },
        ]);
    }

    /// The speed of [`BourgState::speed_ftps`] (the same operations, lane
    /// by lane) and the Euler angles of [`BourgState::euler_angles_deg`]
    /// ([`fdm_core::bourg::ops::euler_deg_from_quat_lanes`]), a block at a
    /// time.
    #[inline(always)]
    fn block_fields<const N: usize>(
        states: &[BourgState; N],
        out: &mut [[f64; N]; MAX_BLOCK_FIELDS],
    ) {
        for (o, s) in out[0].iter_mut().zip(states) {
            *o = f64::from(fdm_core::bourg::ops::magnitude(&s.velocity_ftps));
        }
        let q: [_; N] = core::array::from_fn(|l| states[l].orientation);
        let e = fdm_core::bourg::ops::euler_deg_from_quat_lanes(&q);
        for (l, e) in e.iter().enumerate() {
            out[1][l] = f64::from(e.x);
            out[2][l] = f64::from(e.y);
            out[3][l] = f64::from(e.z);
        }
    }

    #[inline(always)]
    fn control_values(c: &BourgControls, out: &mut [f64]) {
        let rudder = if c.rudder_deg > 0.0 {
            -1.0
        } else if c.rudder_deg < 0.0 {
            1.0
        } else {
            0.0
        };
        out.copy_from_slice(&[
            f64::from(c.thrust_lb),
            flap_code(c.elevators),
            // roll-right: port trailing edge down (−1): aileron +1. No −0.0
            // for neutral.
            0.0 - flap_code(c.port_aileron),
            rudder,
            if c.landing_flaps { 1.0 } else { 0.0 },
            f64::from(c.pitch_trim),
        ]);
    }

    #[inline]
    #[allow(clippy::cast_possible_truncation)] // checked ranges; f32 is the model's type
    fn with_control(
        mut c: BourgControls,
        index: usize,
        value: f64,
    ) -> Result<BourgControls, String> {
        match index {
            0 => c.thrust_lb = value as f32,
            1 => c.elevators = flap_from(value)?,
            2 => {
                c.port_aileron = flap_from(-value)?;
                c.starboard_aileron = flap_from(value)?;
            }
            3 => {
                c.rudder_deg = match value {
                    1.0 => -fdm_core::bourg::RUDDER_DEFLECTION_DEG,
                    -1.0 => fdm_core::bourg::RUDDER_DEFLECTION_DEG,
                    0.0 => 0.0,
                    v => return Err(format!("{v} is not -1, 0 or 1")),
                }
            }
            4 => {
                c.landing_flaps = match value {
                    1.0 => true,
                    0.0 => false,
                    v => return Err(format!("{v} is not 0 or 1")),
                }
            }
            _ => c.pitch_trim = value as f32,
        }
        Ok(c)
    }
}

/// Bourg's all-or-nothing surfaces from an action: +1 above 1/3, -1 below
/// -1/3, else 0 (NaN too), as `_surface`.
#[inline]
#[must_use]
fn surface(a: f64) -> f64 {
    if a > 1.0 / 3.0 {
        1.0
    } else if a < -1.0 / 3.0 {
        -1.0
    } else {
        0.0
    }
}

/// Bourg's controls from one aircraft's clipped actions: thrust_lb,
/// elevator, aileron, rudder, pitch_trim (control indices 0, 1, 2, 3, 5).
#[inline]
#[must_use]
fn bourg_controls(a: &[f64]) -> [(usize, f64); 5] {
    [
        (0, 1500.0 * (a[0] + 1.0)),
        (1, surface(a[1])),
        (2, surface(a[2])),
        (3, surface(a[3])),
        (5, a[4]),
    ]
}

/// A block's columns and controls straight from the kernel's lanes: each
/// lane the per-aircraft methods' operations in the same order, the lanes
/// together (the compiler may put them in vector registers: every operation
/// is correctly rounded, none is fused).
impl LaneAgent for Bourg {
    const BLOCK_READS: bool = true;

    /// The state's columns are the block's own lanes widened to `f64` (the
    /// state's fields in [`ColumnModel::state_values_head`]'s order; the
    /// stall flag 1 or 0), every lane (those past `count` too).
    #[inline(always)]
    fn block_state_values(block: &Block<Self>, _count: usize, out: &mut [[f64; LANES]]) {
        let v = &block.vars;
        let w = |a: &BourgLanes| a.0.map(f64::from);
        let (p, u, b, r, o) = (
            &v.position_ft,
            &v.velocity_ftps,
            &v.velocity_body_ftps,
            &v.angular_velocity_radps,
            &v.orientation,
        );
        let stalling = v.stalling.0.map(|s| if s { 1.0 } else { 0.0 });
        let columns = [
            block.time,
            w(&p.x),
            w(&p.y),
            w(&p.z),
            w(&u.x),
            w(&u.y),
            w(&u.z),
            w(&b.x),
            w(&b.y),
            w(&b.z),
            w(&r.x),
            w(&r.y),
            w(&r.z),
            w(&o.w),
            w(&o.x),
            w(&o.y),
            w(&o.z),
            stalling,
        ];
        for (o, c) in out.iter_mut().zip(&columns) {
            *o = *c;
        }
    }

    /// The speed ([`BourgState::speed_ftps`]'s operations, lane-wise) and
    /// the Euler angles ([`fdm_core::bourg::ops::euler_deg_from_quat_columns`])
    /// of every lane, from the block's own lanes.
    #[inline(always)]
    fn block_tail_values(
        block: &Block<Self>,
        _count: usize,
        out: &mut [[f64; LANES]; MAX_BLOCK_FIELDS],
    ) {
        let v = &block.vars;
        let (u, o) = (&v.velocity_ftps, &v.orientation);
        for (l, speed) in out[0].iter_mut().enumerate() {
            let (x, y, z) = (u.x.0[l], u.y.0[l], u.z.0[l]);
            *speed = f64::from((x * x + y * y + z * z).sqrt());
        }
        let e = fdm_core::bourg::ops::euler_deg_from_quat_columns(&o.w.0, &o.x.0, &o.y.0, &o.z.0);
        for (column, angles) in out[1..].iter_mut().zip(&e) {
            *column = angles.map(f64::from);
        }
    }

    /// [`AgentModel::task_kinematics`] reads four columns as they are.
    #[inline(always)]
    fn block_kinematics(columns: &[[f64; LANES]], out: &mut [[f64; LANES]; 4]) {
        *out = [columns[3], columns[6], columns[4], columns[5]];
    }

    /// [`ColumnModel::control_values`] and [`AgentModel::task_control_obs`]
    /// of every lane (those past `count` hold controls too).
    #[inline(always)]
    fn block_control_obs(
        controls: &[BourgControls; LANES],
        _count: usize,
        out: &mut [[f64; LANES]; MAX_CONTROL_OBS],
    ) {
        for (l, c) in controls.iter().enumerate() {
            let mut values = [0.0; 6];
            let mut observed = [0.0; 5];
            Self::control_values(c, &mut values);
            Self::task_control_obs(&values, &mut observed);
            for (column, v) in out.iter_mut().zip(observed) {
                column[l] = v;
            }
        }
    }
}

impl AgentModel for Bourg {
    const TASK_ACTIONS: usize = 5;
    const TASK_CONTROL_OBS: usize = 5;

    const GROUND_MPS_PER_SPEED: f64 = 0.3048;

    #[inline(always)]
    fn task_kinematics(v: &[f64]) -> Kinematics {
        Kinematics {
            altitude_ft: v[3],
            climb_ftps: v[6],
            vx: v[4],
            vy: v[5],
        }
    }

    #[inline(always)]
    fn task_control_obs(c: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&[c[0] / 3000.0, c[1], c[2], c[3], c[5]]);
    }

    #[inline]
    fn task_controls(a: &[f64]) -> ([(usize, f64); 5], usize) {
        (bourg_controls(a), 5)
    }

    #[inline(always)]
    #[allow(clippy::cast_possible_truncation)] // as with_control: f32 is the model's type
    fn task_apply(mut c: BourgControls, a: &[f64]) -> BourgControls {
        let [(_, thrust), (_, elevator), (_, aileron), (_, rudder), (_, trim)] = bourg_controls(a);
        // `surface` gives exactly -1, 0 or +1 (never -0).
        let flap = |v: f64| flap_from(v).unwrap_or(Flap::Neutral);
        c.thrust_lb = thrust as f32;
        c.elevators = flap(elevator);
        c.port_aileron = flap(-aileron);
        c.starboard_aileron = flap(aileron);
        c.rudder_deg = if rudder == 1.0 {
            -fdm_core::bourg::RUDDER_DEFLECTION_DEG
        } else if rudder == -1.0 {
            fdm_core::bourg::RUDDER_DEFLECTION_DEG
        } else {
            0.0
        };
        c.pitch_trim = trim as f32;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(feature = "dis")]
    use crate::model::test_support::{lanes_against_frames, rough_bits, uniform_in_plus_minus_one};
    use fdm_core::bourg::BourgAction;

    /// The tasks' surfaces (`afit_fdm.gym`'s `_surface`): an action above
    /// 1/3 is +1, below -1/3 is -1, else 0 (1/3 and -1/3 themselves, and
    /// NaN); the thrust spans 0..3000 lb over the action's -1..1; the trim
    /// is the action; the controls set are thrust, elevator, aileron,
    /// rudder and pitch trim (indices 0, 1, 2, 3, 5).
    #[test]
    fn the_tasks_actions_set_thrust_surfaces_and_trim() {
        let third = 1.0_f64 / 3.0;
        for (a, want) in [
            (third, 0.0),
            (third.next_up(), 1.0),
            (-third, 0.0),
            ((-third).next_down(), -1.0),
            (0.0, 0.0),
            (-0.0, 0.0),
            (f64::NAN, 0.0),
            (1.0, 1.0),
            (-1.0, -1.0),
        ] {
            let (list, count) = Bourg::task_controls(&[0.0, a, a, a, 0.0]);
            assert_eq!(count, 5);
            for (index, value) in &list[1..4] {
                assert_eq!(value.to_bits(), f64::to_bits(want), "{a} control {index}");
            }
        }
        for (a, lb) in [(-1.0, 0.0), (0.0, 1500.0), (0.5, 2250.0), (1.0, 3000.0)] {
            let (list, _) = Bourg::task_controls(&[a, 0.0, 0.0, 0.0, -0.25]);
            assert_eq!(
                list,
                [(0, lb), (1, 0.0), (2, 0.0), (3, 0.0), (5, -0.25)],
                "{a}"
            );
        }
    }

    /// An action of +1 or -1 moves a surface as the key press of that
    /// direction does (elevator +1 is pitch-up, aileron +1 roll-right,
    /// rudder +1 yaw-right), and the observed controls of those controls
    /// are the actions back: thrust over 3000 lb, the surfaces' directions,
    /// the trim.
    #[test]
    fn the_tasks_surfaces_are_the_keys_directions() {
        let aircraft = Bourg::default_aircraft();
        let start = Bourg::initial_controls();
        for (sign, keys) in [
            (
                1.0,
                [
                    BourgAction::PitchUp,
                    BourgAction::RollRight,
                    BourgAction::YawRight,
                ],
            ),
            (
                -1.0,
                [
                    BourgAction::PitchDown,
                    BourgAction::RollLeft,
                    BourgAction::YawLeft,
                ],
            ),
        ] {
            let mut want = keys
                .into_iter()
                .fold(start, |c, key| Bourg::apply(&aircraft, c, key));
            want.thrust_lb = 2250.0;
            want.pitch_trim = 0.5;
            let got = Bourg::task_apply(start, &[0.5, sign, sign, sign, 0.5]);
            assert_eq!(got, want, "{sign}");
            let mut values = [0.0; 6];
            Bourg::control_values(&got, &mut values);
            let mut observed = [0.0; 5];
            Bourg::task_control_obs(&values, &mut observed);
            assert_eq!(observed, [0.75, sign, sign, sign, 0.5], "{sign}");
        }
        // Neutral surfaces are observed as +0 (no -0).
        let mut values = [f64::NAN; 6];
        Bourg::control_values(&start, &mut values);
        for v in &values[1..5] {
            assert_eq!(v.to_bits(), 0.0_f64.to_bits(), "{values:?}");
        }
    }

    /// A fleet's offsets are metres, Bourg's position feet (1 ft = 0.3048
    /// m): 30.48 m north, 60.96 m west and 3.048 m down move an aircraft
    /// 100 ft, 200 ft and -10 ft, and nothing else.
    #[test]
    fn an_offset_in_metres_moves_the_feet() {
        let (_, mut state) = Bourg::fleet_member(4);
        state.position_ft = nalgebra::Vector3::new(1000.0, -2000.0, 1500.0);
        let moved = Bourg::offset_state(&state, 30.48, 60.96, -3.048);
        let p = moved.position_ft;
        for (got, want) in [(p.x, 1100.0), (p.y, -1800.0), (p.z, 1490.0)] {
            assert!((got - want).abs() < 1e-3, "{p:?}");
        }
        assert_eq!(
            BourgState {
                position_ft: state.position_ft,
                ..moved
            },
            state
        );
    }

    /// The CSV's position and velocity are the state's, in feet (widened
    /// exactly): times `METRES_PER_UNIT`, the view's metres.
    #[test]
    fn the_csvs_native_columns_are_the_views_in_feet() {
        let aircraft = Bourg::default_aircraft();
        let (controls, mut state) = Bourg::fleet_member(6);
        state.velocity_ftps = nalgebra::Vector3::new(78.0, -12.5, 3.25);
        let view = Bourg::view(&aircraft, &controls, &state);
        let (p, v) = (
            Bourg::native_position(&state),
            Bourg::native_velocity(&state),
        );
        for i in 0..3 {
            assert_eq!(p[i], f64::from(state.position_ft[i]));
            assert_eq!(v[i], f64::from(state.velocity_ftps[i]));
            let (pm, vm) = (view.position_m[i], view.velocity_mps[i]);
            assert!(
                (p[i] * Bourg::METRES_PER_UNIT - pm).abs() <= 1e-9 * pm.abs(),
                "{p:?}"
            );
            assert!(
                (v[i] * Bourg::METRES_PER_UNIT - vm).abs() <= 1e-9 * vm.abs(),
                "{v:?}"
            );
        }
        assert!(p.iter().chain(&v).all(|x| x.abs() > 1.0), "{p:?} {v:?}");
    }

    /// The sample snapshot's airspeed is its speed, 183.12346 ft/s, in m/s.
    #[test]
    fn the_sample_snapshots_airspeed_is_its_speed_in_mps() {
        let s = BourgDetails::sample_snapshot();
        assert_eq!(s.details.speed, f64::from(183.123_46_f32));
        assert!(
            (s.airspeed_mps - 55.816_03).abs() < 1e-5,
            "{}",
            s.airspeed_mps
        );
    }

    /// A study file sets the thrust by name, in 0..3000 lb (`sim-cli bourg
    /// --thrust-lb`'s range); a value out of it, or another name, is
    /// refused naming it.
    #[test]
    fn a_study_sets_the_thrust_by_name() {
        let mut c = Bourg::initial_controls();
        Bourg::set_control(&mut c, "thrust_lb", 1234.5).unwrap();
        assert_eq!(c.thrust_lb, 1234.5);
        Bourg::set_control(&mut c, "thrust_lb", 3000.0).unwrap();
        assert_eq!(c, {
            let mut want = Bourg::initial_controls();
            want.thrust_lb = 3000.0;
            want
        });
        for value in [-1.0, 3000.5, f64::NAN] {
            let refused = Bourg::set_control(&mut c, "thrust_lb", value).unwrap_err();
            assert!(refused.starts_with("thrust_lb = "), "{refused}");
        }
        let refused = Bourg::set_control(&mut c, "throttle", 0.5).unwrap_err();
        assert_eq!(
            refused,
            "unknown control `throttle`; expected one of thrust_lb, landing_flaps, pitch_trim"
        );
        assert_eq!(c.thrust_lb, 3000.0);
    }

    /// The landing flaps by name take exactly 0 (up) or 1 (down), the
    /// column `landing_flaps` of the controls; the pitch trim any number in
    /// the controls' −1..=1, ends included, rounded to f32 once (as the
    /// thrust). Anything else (between, beyond, NaN) is refused naming the
    /// key and what it takes, and leaves the controls as they were.
    #[test]
    fn a_study_sets_the_landing_flaps_and_pitch_trim_by_name() {
        let start = Bourg::initial_controls();
        assert!(!start.landing_flaps);
        for (value, down) in [(1.0, true), (0.0, false)] {
            // From both settings, so the result is the value's own.
            for from in [false, true] {
                let mut c = BourgControls {
                    landing_flaps: from,
                    ..start
                };
                Bourg::set_control(&mut c, "landing_flaps", value).unwrap();
                let want = BourgControls {
                    landing_flaps: down,
                    ..start
                };
                assert_eq!(c, want, "{value} from {from}");
            }
        }
        for (value, trim) in [
            (-1.0, -1.0_f32),
            (1.0, 1.0),
            (0.0, 0.0),
            (0.25, 0.25),
            (-0.1, -0.1),
        ] {
            let mut c = BourgControls {
                pitch_trim: 0.5,
                ..start
            };
            Bourg::set_control(&mut c, "pitch_trim", value).unwrap();
            assert_eq!(
                c,
                BourgControls {
                    pitch_trim: trim,
                    ..start
                },
                "{value}"
            );
        }
        let set = BourgControls {
            landing_flaps: true,
            pitch_trim: 0.5,
            ..start
        };
        let mut c = set;
        for (key, value, refusal) in [
            ("landing_flaps", 2.0, "landing_flaps = 2: expected 0 or 1"),
            ("landing_flaps", 0.5, "landing_flaps = 0.5: expected 0 or 1"),
            (
                "landing_flaps",
                -0.5,
                "landing_flaps = -0.5: expected 0 or 1",
            ),
            ("landing_flaps", -1.0, "landing_flaps = -1: expected 0 or 1"),
            ("landing_flaps", 10.0, "landing_flaps = 10: expected 0 or 1"),
            (
                "landing_flaps",
                f64::NAN,
                "landing_flaps = NaN: expected 0 or 1",
            ),
            (
                "pitch_trim",
                1.5,
                "pitch_trim = 1.5: expected a number from -1 to 1",
            ),
            (
                "pitch_trim",
                -1.0001,
                "pitch_trim = -1.0001: expected a number from -1 to 1",
            ),
            (
                "pitch_trim",
                f64::NAN,
                "pitch_trim = NaN: expected a number from -1 to 1",
            ),
        ] {
            assert_eq!(
                Bourg::set_control(&mut c, key, value),
                Err(refusal.to_owned())
            );
            assert_eq!(c, set);
        }
    }

    /// `CONTROL_KEYS` is exactly what `set_control` takes: each key, in
    /// order, sets its own field (each value another than the start's), and
    /// a name that is not one (the other columns of the controls, set per
    /// frame, among them) is refused listing them.
    #[test]
    fn the_control_keys_are_what_set_control_takes() {
        let values = [
            ("thrust_lb", 2500.0),
            ("landing_flaps", 1.0),
            ("pitch_trim", -0.5),
        ];
        let all = crate::model::test_support::each_control_key_sets_its_own_field::<Bourg>(
            &values,
            |key| key,
        );
        let start = Bourg::initial_controls();
        let want = BourgControls {
            thrust_lb: 2500.0,
            landing_flaps: true,
            pitch_trim: -0.5,
            ..start
        };
        assert_eq!(all, want);
        for key in ["elevator", "rudder_deg", "flaps", "Pitch_trim", ""] {
            assert_eq!(
                Bourg::set_control(&mut { all }, key, 0.0),
                Err(unknown_key("control", key, Bourg::CONTROL_KEYS))
            );
        }
    }

    /// A study file's aircraft parameters: the mass and area scales
    /// multiply every element's mass and area, the thrust limits are set;
    /// a scale outside 0.01..100 or another name is refused naming it.
    #[test]
    fn a_study_sets_the_aircraft_by_name() {
        let default = BourgAircraft::bourg_default();
        let a = Bourg::aircraft_with(&[
            ("mass_scale", 2.0),
            ("area_scale", 0.5),
            ("max_thrust_lb", 2000.0),
            ("delta_thrust_lb", 25.0),
        ])
        .unwrap();
        for (e, d) in a
            .airframe()
            .elements
            .iter()
            .zip(&default.airframe().elements)
        {
            assert_eq!(e.mass_slug, d.mass_slug * 2.0);
            assert_eq!(e.area_ft2, d.area_ft2 * 0.5);
        }
        let mass = |a: &BourgAircraft| a.mass_properties().mass_slug;
        assert!((mass(&a) / mass(&default) - 2.0).abs() < 1e-5);
        assert_eq!((a.max_thrust_lb, a.delta_thrust_lb), (2000.0, 25.0));
        assert_eq!(Bourg::aircraft_with(&[]), Ok(default));
        for (key, value) in [
            ("mass_scale", 0.001),
            ("area_scale", 101.0),
            ("max_thrust_lb", -1.0),
        ] {
            let refused = Bourg::aircraft_with(&[(key, value)]).unwrap_err();
            assert!(refused.starts_with(&format!("{key} = ")), "{refused}");
        }
        assert!(Bourg::aircraft_with(&[("mass", 1.0)])
            .unwrap_err()
            .starts_with("unknown aircraft parameter `mass`"));
    }

    /// `sim-cli bourg`'s start: the model's own without `--thrust-lb`, its
    /// thrust with it; and the HUD's controls line (the example of
    /// `ControlsLine::controls_line`).
    #[test]
    fn the_pilots_start_and_controls_line() {
        use crate::model::pilot::{ControlsLine, OptionValue, PilotModel};
        let initial = Bourg::initial_controls();
        assert_eq!(Bourg::start_controls(&[OptionValue::Absent]), Ok(initial));
        let mut want = initial;
        want.thrust_lb = 1234.5;
        assert_eq!(
            Bourg::start_controls(&[OptionValue::Number(1234.5)]),
            Ok(want)
        );
        let details = Bourg::details(
            &Bourg::default_aircraft(),
            &initial,
            &Bourg::initial_state(),
        );
        assert_eq!(
            details.controls_line(),
            "THRUST  500 lb   FLAPS up   TRIM +0.00"
        );
        let sample = BourgDetails::sample_snapshot().details;
        assert_eq!(
            sample.controls_line(),
            "THRUST 3000 lb   FLAPS down   TRIM +0.00"
        );
    }

    /// The cheap reads of a state in flight (its time past 0) are the
    /// view's, bit for bit.
    #[test]
    fn the_cheap_reads_of_a_flight_are_the_views() {
        crate::model::test_support::cheap_reads_are_the_views::<Bourg>();
    }

    /// What a recording keeps of a state is the state half of fdm-core's
    /// fingerprint (the docs of `RunModel::state_fingerprint`), so a state a
    /// step on has another.
    #[test]
    fn the_recorded_fingerprint_is_the_states() {
        crate::model::test_support::recorded_fingerprint_is_the_states::<Bourg>(
            |s| fingerprint::Fingerprint::of_bourg(s).state,
            &[],
        );
    }

    /// A recorded aircraft comes back as it was (airframe and thrust
    /// limits), and a record whose thrust limit is not a finite number of
    /// at least 0 lb is refused naming the field; 0 lb is accepted.
    #[test]
    fn a_recorded_aircraft_comes_back_and_bad_thrust_limits_are_refused() {
        let aircraft = Bourg::aircraft_with(&[
            ("mass_scale", 1.5),
            ("max_thrust_lb", 2500.0),
            ("delta_thrust_lb", 50.0),
        ])
        .unwrap();
        assert_ne!(aircraft, BourgAircraft::bourg_default());
        let record = Bourg::aircraft_record(&aircraft);
        assert_eq!(Bourg::aircraft_from_record(record), Ok(aircraft));
        for name in ["max_thrust_lb", "delta_thrust_lb"] {
            let with = |value: f32| {
                let mut r = record;
                match name {
                    "max_thrust_lb" => r.max_thrust_lb = value,
                    _ => r.delta_thrust_lb = value,
                }
                Bourg::aircraft_from_record(r)
            };
            let zero = with(0.0).unwrap();
            assert_eq!(zero.airframe(), aircraft.airframe(), "{name}");
            for value in [-1.0, -0.001, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                assert_eq!(
                    with(value),
                    Err(format!("{name} {value} is not a finite thrust >= 0")),
                    "{name} {value}"
                );
            }
        }
    }

    /// The sample snapshot's Euler angles are its common state's attitude
    /// (`CommonState::sample`: roll 5°, pitch 2.5°, heading 359.5°) read in
    /// the model's axes by `bourg_attitude`, the mapping a flight's view
    /// uses (x roll, y pitch nose-down, z yaw left: pitch -y, heading -z
    /// wrapped to [0, 360)). The numbers are exact in `f32` and the mapping
    /// is a sign change and one addition of 360, so they compare exactly.
    #[test]
    fn the_sample_snapshots_euler_angles_are_its_attitude() {
        let s = BourgDetails::sample_snapshot();
        let euler = nalgebra::Vector3::from(s.details.euler_deg.map(|d| d as f32));
        assert_eq!(<[f64; 3]>::from(euler.map(f64::from)), s.details.euler_deg);
        let a = fdm_core::geodesy::bourg_attitude(euler);
        let common = s.common.attitude_deg;
        assert_eq!(
            (a.roll_deg, a.pitch_deg, a.heading_deg),
            (common.roll, common.pitch, common.heading)
        );
    }

    /// States for the rough DIS frames: orientations in every direction
    /// (random quaternions, normalised or off by a few 1e-6 as a step
    /// leaves them) and from Euler angles (banked, inverted, at the
    /// vertical), with positions and velocities in feet.
    #[cfg(feature = "dis")]
    fn rough_states(n: usize) -> Vec<Option<BourgState>> {
        use fdm_core::bourg::{ops, Quaternion};
        let mut next = uniform_in_plus_minus_one();
        (0..n)
            .map(|i| {
                let orientation = if i % 3 == 0 {
                    let euler = nalgebra::Vector3::new(
                        180.0 * next(),
                        if i % 9 == 0 { 90.0 } else { 89.0 * next() },
                        180.0 * next(),
                    );
                    ops::quat_from_euler_deg(&euler.map(|c| c as f32))
                } else {
                    let q = Quaternion::new(next(), next(), next(), next()).cast::<f32>();
                    let (n, scale) = (q.norm(), 1.0 + 4e-6 * next() as f32);
                    Quaternion::from_vector(q.coords.map(|c| c / n * scale))
                };
                let mut s = BourgState::initial();
                s.time_s = i as f64 / 30.0;
                s.position_ft = nalgebra::Vector3::new(i as f32 * 1.7 + 3.0, -3.3, 2000.0);
                s.velocity_ftps =
                    nalgebra::Vector3::new(next(), next(), next()).map(|c| (c * 300.0) as f32);
                s.orientation = orientation;
                Some(s)
            })
            .collect()
    }

    /// `FleetModel::dis_rough` (`bourg_rough`): each aircraft's view's
    /// time, position, velocity and attitude matrix, bit for bit (its docs;
    /// the view is fdm-core's `Bourg::view`), over orientations in every
    /// direction; none for an aircraft without a state or with a number
    /// that is not finite. And from independent numbers: an aircraft 100 ft
    /// north, 200 ft west and 1000 ft up, flying 10 ft/s north, 20 ft/s west
    /// and 5 ft/s up, heading east (yaw -90°) 30° nose-up, is 30.48 m,
    /// 60.96 m and 304.8 m there at 3.048, 6.096 and 1.524 m/s (to 1e-12
    /// of each: one rounding of the product), and its nose (the matrix's
    /// first column, north-east-down) is (0, cos 30°, -sin 30°), to 1e-5
    /// (the quaternion and the Euler angles are `f32`: a few 1e-7 rad).
    #[cfg(feature = "dis")]
    #[test]
    fn the_rough_frames_are_the_views() {
        let aircraft = Bourg::default_aircraft();
        let mut states = rough_states(300);
        states[7] = None;
        states[11].as_mut().unwrap().position_ft.y = f32::NAN;
        states[13].as_mut().unwrap().velocity_ftps.z = f32::INFINITY;
        states[17].as_mut().unwrap().orientation.coords.x = f32::NAN;
        states[19].as_mut().unwrap().time_s = f64::NAN;
        let mut out = vec![None; states.len()];
        Bourg::dis_rough(0, &states, &mut out);
        let mut made = 0;
        for (i, (s, r)) in states.iter().zip(&out).enumerate() {
            let Some(s) = s.filter(BourgState::is_finite) else {
                assert!(r.is_none(), "aircraft {i}: {r:?}");
                continue;
            };
            let r = r.unwrap_or_else(|| panic!("no rough frame for aircraft {i}"));
            let view = Bourg::view(&aircraft, &Bourg::fleet_member(i).0, &s);
            let want = fdm_dis::Rough {
                time_s: view.time_s,
                position_m: view.position_m,
                velocity_mps: view.velocity_mps,
                body_to_ned: view.attitude.body_to_ned(),
            };
            assert_eq!(rough_bits(&r), rough_bits(&want), "aircraft {i}");
            made += 1;
        }
        assert_eq!(made, 300 - 5);

        let mut s = BourgState::initial();
        s.position_ft = nalgebra::Vector3::new(100.0, 200.0, 1000.0);
        s.velocity_ftps = nalgebra::Vector3::new(10.0, 20.0, 5.0);
        s.orientation =
            fdm_core::bourg::ops::quat_from_euler_deg(&nalgebra::Vector3::new(0.0, -30.0, -90.0));
        let mut out = [None];
        Bourg::dis_rough(3, &[Some(s)], &mut out);
        let r = out[0].expect("a rough frame");
        let close = |got: f64, want: f64| (got - want).abs() <= 1e-12 * want.abs();
        for (got, want) in r.position_m.iter().zip([30.48, 60.96, 304.8]) {
            assert!(close(*got, want), "{}", r.position_m);
        }
        for (got, want) in r.velocity_mps.iter().zip([3.048, 6.096, 1.524]) {
            assert!(close(*got, want), "{}", r.velocity_mps);
        }
        let nose = r.body_to_ned.column(0);
        let half_root_3 = 3.0_f64.sqrt() / 2.0;
        for (got, want) in nose.iter().zip([0.0, half_root_3, -0.5]) {
            assert!((got - want).abs() < 1e-5, "{nose}");
        }
    }

    /// `FleetModel::dis_rough_lanes` (`bourg_rough_lanes`) is
    /// `bourg_rough` lane by lane, bit for bit (its docs), a lane without a
    /// rough frame not `ok`: full groups of eight, groups with aircraft
    /// without a state or with a number that is not finite, and a last
    /// group of fewer than eight; each lane's matrix element `(i / 3, i %
    /// 3)` in its place (the orientations are general, so no two elements
    /// are the same).
    #[cfg(feature = "dis")]
    #[test]
    fn the_rough_lanes_are_the_rough_frames() {
        const L: usize = fdm_dis::ROUGH_LANES;
        let mut states = rough_states(4 * L + 5);
        states[L + 2] = None;
        states[L + 5].as_mut().unwrap().position_ft.z = f32::NAN;
        states[2 * L].as_mut().unwrap().angular_velocity_radps.x = f32::INFINITY;
        states[2 * L + 7].as_mut().unwrap().orientation.coords.w = f32::NAN;
        let mut want = vec![None; states.len()];
        bourg_rough(&states, &mut want);
        let (made, none) = lanes_against_frames::<Bourg>(&states, &want);
        assert_eq!((made, none), (states.len() - 4, 4));
    }
}
