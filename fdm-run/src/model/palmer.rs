//! Palmer's Cessna 172 in the run library: everything the registry needs of
//! it in one place. A recording keeps its aircraft as is ([`RunModel`]);
//! fleets fly it in `fdm_fleet::Fleet<Palmer>` and FlightGear draws the
//! c172p ([`FleetModel`]); the flight CSV's columns ([`CsvModel`]) and the
//! report's fields ([`ReportModel`], [`PalmerDetails`]); the controls and
//! parameters a study file sets by name ([`NamedInputs`]).

use fdm_core::fingerprint;
use fdm_core::model::FlightStatus;
#[cfg(feature = "dis")]
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerAircraft, PalmerControls, PalmerState};
use serde::{Deserialize, Serialize};

use crate::csv::CsvModel;
use crate::model::{in_range, not_one_of, unknown_key, NamedInputs};
use crate::report::{CommonState, Details, ReportModel, Snapshot};
use crate::{FleetModel, RunModel};
use fdm_core::palmer::{ALPHA_MAX_DEG, ALPHA_MIN_DEG, BANK_LIMIT_DEG};

impl RunModel for Palmer {
    type AircraftRecord = PalmerAircraft;

    const ACMI_NAME: &'static str = "C172";
    const CALLSIGN: &'static str = "C172";
    #[cfg(feature = "dis")]
    const DIS_KIND: fdm_dis::AircraftKind = fdm_dis::AircraftKind::CESSNA_172_SKYHAWK;
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
    /// the Euler angles ([`palmer_rough`]).
    #[cfg(feature = "dis")]
    fn dis_rough(first: usize, states: &[Option<PalmerState>], out: &mut [Option<fdm_dis::Rough>]) {
        palmer_rough(first, states, out);
    }

    /// [`palmer_rough_lanes`]: the same frames lane by lane.
    #[cfg(feature = "dis")]
    #[inline(always)]
    fn dis_rough_lanes(
        first: usize,
        states: &[Option<PalmerState>],
        out: &mut fdm_dis::RoughLanes,
    ) {
        palmer_rough_lanes(first, states, out);
    }
}

/// [`FleetModel::dis_rough`] for Palmer's demonstration fleet: aircraft
/// `first + k` with state `states[k]` and the controls of
/// [`Model::fleet_member`]`(first + k)`, its body-to-NED matrix made straight
/// from the velocity and controls, eight aircraft at a time (the sines and
/// cosines of the angle of attack and the bank by
/// [`fdm_core::math::sin_cos_lanes`]).
///
/// [`fdm_core::geodesy::palmer_attitude`] makes the matrix
/// `C = Rz(track) · Ry(climb) · Rx(bank) · Ry(alpha)` with `track` and
/// `climb` from `atan2` and `hypot` of the velocity, then reads three Euler
/// angles from it (three `atan2`, a `hypot`), which the DIS placement turns
/// back into a matrix (three `sin_cos`). Here the sine and cosine of `track`
/// and `climb` are the velocity's ratios (`vx / vh`, `-vy / vh`, `vh / v`,
/// `vz / v`) and there are no angles: the same matrix up to rounding
/// (1e-15 in each element) and to the Euler round trip, whose roll and
/// heading lose about `1e-16 / cos(pitch)` each. So an aircraft gets a
/// rough frame only when
///
/// * its time and position are finite (the frame carries them as they
///   are; the exact path decides what a state that is not finite sends),
/// * its velocity components are 0 or between 1e-100 and 1e100 m/s in
///   magnitude, the horizontal ones both 0 or the larger of them in that
///   range (no square under- or overflows beyond a relative 1e-100), and
/// * `cos(pitch)² = C₀₀² + C₁₀² ≥ 1e-6` (at least 0.06° from the vertical),
///
/// which keeps every element within about 1e-12 of the exact path's, a
/// thousandth of [`fdm_dis::ROUGH_TOLERANCE`] (the test
/// `palmer_rough_is_within_the_tolerance` measures it on states near the
/// limits); any other aircraft (and any non-finite result) takes the exact
/// path.
#[cfg(feature = "dis")]
pub fn palmer_rough(
    first: usize,
    states: &[Option<PalmerState>],
    out: &mut [Option<fdm_dis::Rough>],
) {
    const L: usize = 8;
    for (c, (states, out)) in states.chunks(L).zip(out.chunks_mut(L)).enumerate() {
        // Lanes past the end get an angle in sin_cos_lanes's kernel range.
        let mut alpha = [0.1; L];
        let mut bank = [0.1; L];
        for (k, (a, b)) in alpha
            .iter_mut()
            .zip(&mut bank)
            .take(states.len())
            .enumerate()
        {
            let (controls, _) = Palmer::fleet_member(first + c * L + k);
            *a = controls.alpha_deg.to_radians();
            *b = controls.bank_deg.to_radians();
        }
        let (sin_alpha, cos_alpha) = fdm_core::math::sin_cos_lanes(alpha);
        let (sin_bank, cos_bank) = fdm_core::math::sin_cos_lanes(bank);
        for (k, (s, o)) in states.iter().zip(out.iter_mut()).enumerate() {
            *o = s.and_then(|s| {
                palmer_rough_one(&s, (sin_alpha[k], cos_alpha[k]), (sin_bank[k], cos_bank[k]))
            });
        }
    }
}

/// [`palmer_rough`] for up to [`fdm_dis::ROUGH_LANES`] aircraft, lane by
/// lane (`out`'s lanes `k < states.len()`; `ok[k]` false where
/// [`palmer_rough`] makes none): the same operations in the same order as
/// [`palmer_rough`]'s for each aircraft, so the same bits (the test
/// `palmer_rough_lanes_is_palmer_rough`), with its branches made selects, in
/// one loop over the lanes that the compiler puts in vector registers.
/// Always inlined, so that the fleet screen's instruction set (pulp's
/// dispatch around it) compiles it too.
#[cfg(feature = "dis")]
#[inline(always)]
// The lane index reads several arrays at once: range loops say so.
#[allow(
    clippy::similar_names,
    clippy::many_single_char_names,
    clippy::needless_range_loop
)]
pub fn palmer_rough_lanes(
    first: usize,
    states: &[Option<PalmerState>],
    out: &mut fdm_dis::RoughLanes,
) {
    const L: usize = fdm_dis::ROUGH_LANES;
    // Lanes past the end get an angle in sin_cos_lanes's kernel range.
    let mut alpha = [0.1; L];
    let mut bank = [0.1; L];
    for k in 0..states.len().min(L) {
        let (controls, _) = Palmer::fleet_member(first + k);
        alpha[k] = controls.alpha_deg.to_radians();
        bank[k] = controls.bank_deg.to_radians();
    }
    // Each field's lanes made as one value and stored whole (0 where there
    // is no state; such a lane is not `ok` and never read for a decision):
    // the screen's vector loads of them then read whole stores, instead of
    // eight scalar stores each, which a vector load cannot take from the
    // store buffer (it would wait for every older store to reach the cache).
    let has: [bool; L] = core::array::from_fn(|k| states.get(k).is_some_and(Option::is_some));
    let v = [
        lanes_of(states, |s| s.velocity_mps.x),
        lanes_of(states, |s| s.velocity_mps.y),
        lanes_of(states, |s| s.velocity_mps.z),
    ];
    out.time_s = lanes_of(states, |s| s.time_s);
    out.position_m = [
        lanes_of(states, |s| s.position_m.x),
        lanes_of(states, |s| s.position_m.y),
        lanes_of(states, |s| s.position_m.z),
    ];
    out.velocity_mps = v;
    // A zero angle (the fleet's wings-level aircraft) is outside
    // sin_cos_lanes's kernel range, which would send all eight lanes through
    // the scalar `sin_cos`: such a lane gets an angle in the range, and then
    // `sin_cos`'s own result for ±0, (±0, 1) (fdlibm returns the argument
    // and 1 below 2⁻²⁷), is put back.
    let zero = |x: [f64; L]| x.map(|x| x == 0.0);
    let (alpha_zero, bank_zero) = (zero(alpha), zero(bank));
    let in_kernel = |x: [f64; L]| x.map(|x| if x == 0.0 { 0.1 } else { x });
    let (mut sin_alpha, mut cos_alpha) = fdm_core::math::sin_cos_lanes(in_kernel(alpha));
    let (mut sin_bank, mut cos_bank) = fdm_core::math::sin_cos_lanes(in_kernel(bank));
    for k in 0..L {
        if alpha_zero[k] {
            (sin_alpha[k], cos_alpha[k]) = (alpha[k], 1.0);
        }
        if bank_zero[k] {
            (sin_bank[k], cos_bank[k]) = (bank[k], 1.0);
        }
    }
    for k in 0..L {
        let (vx, vy, vz) = (v[0][k], v[1][k], v[2][k]);
        let (sa, ca, sb, cb) = (sin_alpha[k], cos_alpha[k], sin_bank[k], cos_bank[k]);
        let in_range = |m: f64| (m == 0.0) | (1e-100..1e100).contains(&m);
        let horizontal = vx.abs().max(vy.abs());
        let placed = out.time_s[k].is_finite()
            & out.position_m[0][k].is_finite()
            & out.position_m[1][k].is_finite()
            & out.position_m[2][k].is_finite();
        let usable = has[k]
            & placed
            & vx.is_finite()
            & vy.is_finite()
            & vz.is_finite()
            & in_range(horizontal)
            & in_range(vz.abs());
        let vh2 = vx * vx + vy * vy;
        let vh = fdm_core::math::sqrt(vh2);
        let level = horizontal == 0.0;
        let per_vh = 1.0 / vh;
        let (ct, st) = (
            if level { 1.0 } else { vx * per_vh },
            if level { 0.0 } else { -vy * per_vh },
        );
        let still = level & (vz == 0.0);
        let per_speed = 1.0 / fdm_core::math::sqrt(vh2 + vz * vz);
        let (cc, sc) = (
            if still { 1.0 } else { vh * per_speed },
            if still { 0.0 } else { vz * per_speed },
        );
        // Rz(track) · Ry(climb) and Rx(bank) · Ry(alpha), row by row, and
        // their product as nalgebra's 3 × 3 product makes it.
        let a = [ct * cc, -st, ct * sc, st * cc, ct, st * sc, -sc, 0.0, cc];
        let b = [ca, 0.0, sa, sb * sa, cb, -sb * ca, -cb * sa, sb, cb * ca];
        let c: [f64; 9] = core::array::from_fn(|e| {
            let (i, j) = (e / 3, e % 3);
            a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j]
        });
        let cos_pitch_sq = c[0] * c[0] + c[3] * c[3];
        let finite = c.iter().fold(true, |all, e| all & e.is_finite());
        out.ok[k] = usable & (cos_pitch_sq >= 1e-6) & finite;
        for (e, x) in c.iter().enumerate() {
            out.body_to_ned[e][k] = *x;
        }
    }
    for ok in out.ok.iter_mut().skip(states.len()) {
        *ok = false;
    }
}

/// `field` of the first [`fdm_dis::ROUGH_LANES`] states, lane by lane (0
/// where there is none).
#[cfg(feature = "dis")]
#[inline(always)]
fn lanes_of(
    states: &[Option<PalmerState>],
    field: impl Fn(&PalmerState) -> f64,
) -> [f64; fdm_dis::ROUGH_LANES] {
    core::array::from_fn(|k| states.get(k).and_then(Option::as_ref).map_or(0.0, &field))
}

/// One aircraft of [`palmer_rough`].
#[cfg(feature = "dis")]
fn palmer_rough_one(
    s: &PalmerState,
    (sa, ca): (f64, f64),
    (sb, cb): (f64, f64),
) -> Option<fdm_dis::Rough> {
    let v = s.velocity_mps;
    let in_range = |m: f64| m == 0.0 || (1e-100..1e100).contains(&m);
    let horizontal = v.x.abs().max(v.y.abs());
    // `is_finite`: the time, the position and the velocity.
    if !(s.is_finite() && in_range(horizontal) && in_range(v.z.abs())) {
        return None;
    }
    let vh2 = v.x * v.x + v.y * v.y;
    let vh = fdm_core::math::sqrt(vh2);
    // The degenerate cases as palmer_attitude (and the model) take them.
    // One division each (a rounding more than a quotient: within 1e-15).
    let (ct, st) = if horizontal == 0.0 {
        (1.0, 0.0)
    } else {
        let per_vh = 1.0 / vh;
        (v.x * per_vh, -v.y * per_vh)
    };
    let (cc, sc) = if horizontal == 0.0 && v.z == 0.0 {
        (1.0, 0.0)
    } else {
        let per_speed = 1.0 / fdm_core::math::sqrt(vh2 + v.z * v.z);
        (vh * per_speed, v.z * per_speed)
    };
    // Rz(track) · Ry(climb) and Rx(bank) · Ry(alpha), written out.
    let a = nalgebra::Matrix3::new(ct * cc, -st, ct * sc, st * cc, ct, st * sc, -sc, 0.0, cc);
    let b = nalgebra::Matrix3::new(ca, 0.0, sa, sb * sa, cb, -sb * ca, -cb * sa, sb, cb * ca);
    let c = a * b;
    let cos_pitch_sq = c[(0, 0)] * c[(0, 0)] + c[(1, 0)] * c[(1, 0)];
    if !(cos_pitch_sq >= 1e-6 && c.iter().all(|e| e.is_finite())) {
        return None;
    }
    Some(fdm_dis::Rough {
        time_s: s.time_s,
        position_m: s.position_m,
        velocity_mps: v,
        body_to_ned: c,
    })
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

impl PalmerDetails {
    /// A fixed snapshot (the same in every call) of a Cessna at 55.6 m/s,
    /// 75 % throttle, 4° of attack, banked 5°, 20° of flaps, on
    /// [`CommonState::sample`](crate::report::CommonState::sample): for
    /// tests and examples of code that shows a snapshot.
    #[must_use]
    pub fn sample_snapshot() -> Snapshot<Self> {
        Snapshot {
            common: CommonState::sample(),
            details: Self {
                airspeed: 55.6,
                controls: PalmerControlsReport {
                    throttle: 0.75,
                    alpha_deg: 4.0,
                    bank_deg: 5.0,
                    flaps_deg: 20.0,
                    brakes: false,
                },
                climb_angle_deg: 3.1,
                climb_rate: 2.9,
                heading_deg: 0.5,
            },
            status: FlightStatus::Airborne,
            stalling: false,
            airspeed_mps: 55.6,
        }
    }
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

/// What a study file can set of the model by name, and its cheap reads.
impl NamedInputs for Palmer {
    const CONTROL_KEYS: &'static [&'static str] =
        &["throttle", "alpha_deg", "bank_deg", "flaps_deg", "brakes"];
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
        // The ranges of `sim-cli palmer --throttle/--alpha/--bank`, its
        // flap notches (`--flaps`: exactly 0, 20 or 40, no rounding to the
        // nearest) and its brakes (`--brakes`, on or off: 1 or 0).
        match key {
            "throttle" => controls.throttle = in_range(key, value, 0.0, 1.0)?,
            "alpha_deg" => {
                controls.alpha_deg = in_range(key, value, ALPHA_MIN_DEG, ALPHA_MAX_DEG)?;
            }
            "bank_deg" => {
                controls.bank_deg = in_range(key, value, -BANK_LIMIT_DEG, BANK_LIMIT_DEG)?;
            }
            "flaps_deg" => {
                controls.flaps = [Flaps::Up, Flaps::Deg20, Flaps::Deg40]
                    .into_iter()
                    .find(|flaps| flaps.degrees() == value)
                    .ok_or_else(|| not_one_of(key, value, "0, 20 or 40"))?;
            }
            "brakes" => {
                controls.brakes = [false, true]
                    .into_iter()
                    .find(|&on| f64::from(u8::from(on)) == value)
                    .ok_or_else(|| not_one_of(key, value, "0 or 1"))?;
            }
            _ => return Err(unknown_key("control", key, Self::CONTROL_KEYS)),
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
                _ => return Err(unknown_key("aircraft parameter", key, Self::AIRCRAFT_KEYS)),
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

// --- Flown by hand from a front end (`sim-cli palmer`): start options, keys, HUD line.

use crate::model::pilot::{
    tenths, Choices, ControlsLine, Key, KeyBindings, NumberRange, OptionValue, PilotModel,
    RangeNote, StartOption,
};
use fdm_core::palmer::{Flaps, PalmerAction};

/// `--throttle`, `--alpha`, `--bank`, `--flaps`, `--brakes`: the ranges the
/// keys clamp to ([`ALPHA_MIN_DEG`]..[`ALPHA_MAX_DEG`], [`BANK_LIMIT_DEG`]
/// either side), the model's three flap notches.
impl PilotModel for Palmer {
    const AIRCRAFT: &'static str = "Palmer's Cessna 172";
    const ABOUT: &'static str = "Fly Grant Palmer's Cessna 172 (point mass, RK4, f64; metres, m/s)";
    const START_OPTIONS: &'static [StartOption] = &[
        StartOption::number(
            "throttle",
            "FRACTION",
            "Throttle at frame 0, as a fraction of full power (0..1)",
            NumberRange {
                low: 0.0,
                high: 1.0,
                note: RangeNote::Unit(" (fraction of full power)"),
            },
            Some("0"),
        ),
        StartOption::number(
            "alpha",
            "DEG",
            "Angle of attack at frame 0, degrees (-16..20)",
            NumberRange {
                low: ALPHA_MIN_DEG,
                high: ALPHA_MAX_DEG,
                note: RangeNote::Unit(" degrees"),
            },
            Some("0"),
        ),
        StartOption::number(
            "bank",
            "DEG",
            "Bank angle at frame 0, degrees, positive banks right (-20..20)",
            NumberRange {
                low: -BANK_LIMIT_DEG,
                high: BANK_LIMIT_DEG,
                note: RangeNote::Unit(" degrees"),
            },
            Some("0"),
        ),
        StartOption::choice(
            "flaps",
            "0|20|40",
            "Flap setting at frame 0, degrees (0, 20 or 40)",
            Choices {
                values: &["0", "20", "40"],
                what: "a flap setting (0, 20 or 40)",
            },
            "0",
        ),
        StartOption::flag(
            "brakes",
            "Wheel brakes set at frame 0 (our extension; keys B/V, script actions brakes-on/brakes-off)",
        ),
    ];

    fn start_controls(values: &[OptionValue]) -> Result<PalmerControls, String> {
        use OptionValue::{Choice, Flag, Number};
        let &[Number(throttle), Number(alpha_deg), Number(bank_deg), Choice(flaps), Flag(brakes)] =
            values
        else {
            return Err(crate::model::pilot::unexpected_values(values));
        };
        let flaps = flaps
            .parse()
            .ok()
            .and_then(Flaps::from_degrees)
            .ok_or_else(|| format!("--flaps {flaps}: not a flap setting (0, 20 or 40)"))?;
        Ok(PalmerControls {
            throttle,
            alpha_deg,
            bank_deg,
            flaps,
            brakes,
        })
    }
}

impl KeyBindings for PalmerAction {
    const KEYS: &'static [(Key, Self)] = &[
        (Key::Char('e'), Self::ThrottleUp),
        (Key::Char('d'), Self::ThrottleDown),
        (Key::Down, Self::AlphaUp),
        (Key::Up, Self::AlphaDown),
        (Key::Left, Self::BankLeft),
        (Key::Right, Self::BankRight),
        (Key::Char('k'), Self::FlapsDown),
        (Key::Char('l'), Self::FlapsUp),
        (Key::Char('b'), Self::BrakesOn),
        (Key::Char('v'), Self::BrakesOff),
    ];
    const KEY_HELP: &'static str =
        "E/D throttle  Down/Up alpha +/-  Left/Right bank  K flaps down  L flaps up  B/V brakes on/off";
}

impl ControlsLine for PalmerDetails {
    fn controls_line(&self) -> String {
        let c = &self.controls;
        format!(
            "THROTTLE {:3.0} %   ALPHA {:+5.1} deg   BANK {:+5.1} deg   FLAPS {:.0} deg{}",
            c.throttle * 100.0,
            tenths(c.alpha_deg),
            tenths(c.bank_deg),
            c.flaps_deg,
            brakes_note(c.brakes),
        )
    }
}

// --- Named columns and the agent's tasks (`ColumnModel`, `AgentModel`: the
// Python bindings' state and control columns and Gymnasium tasks).

use fdm_core::palmer::LANES;
use fdm_core::real::kernel::Block;

use super::agent::{AgentModel, Kinematics, LaneAgent, FT_PER_M, MAX_CONTROL_OBS};
use super::columns::{ColumnModel, ControlRange};

impl ColumnModel for Palmer {
    const STATE_FIELDS: &'static [&'static str] =
        &["time_s", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"];
    const CONTROL_FIELDS: &'static [ControlRange] = &[
        ("throttle", 0.0, 1.0),
        ("alpha_deg", ALPHA_MIN_DEG, ALPHA_MAX_DEG),
        ("bank_deg", -BANK_LIMIT_DEG, BANK_LIMIT_DEG),
        ("flaps_deg", 0.0, 40.0),
        ("brakes", 0.0, 1.0),
    ];

    // The trim's throttle and angle of attack replace the given ones.
    const TRIM_SETS: &'static [(&'static str, &'static str)] = &[];

    #[inline]
    fn state_values(s: &PalmerState, out: &mut [f64]) {
        out.copy_from_slice(&[
            s.time_s,
            s.position_m.x,
            s.position_m.y,
            s.position_m.z,
            s.velocity_mps.x,
            s.velocity_mps.y,
            s.velocity_mps.z,
        ]);
    }

    #[inline]
    fn control_values(c: &PalmerControls, out: &mut [f64]) {
        out.copy_from_slice(&[
            c.throttle,
            c.alpha_deg,
            c.bank_deg,
            c.flaps.degrees(),
            if c.brakes { 1.0 } else { 0.0 },
        ]);
    }

    #[inline]
    fn with_control(
        mut c: PalmerControls,
        index: usize,
        value: f64,
    ) -> Result<PalmerControls, String> {
        match index {
            0 => c.throttle = value,
            1 => c.alpha_deg = value,
            2 => c.bank_deg = value,
            3 => {
                c.flaps = [Flaps::Up, Flaps::Deg20, Flaps::Deg40]
                    .into_iter()
                    .find(|f| f.degrees() == value)
                    .ok_or_else(|| format!("{value} is not 0, 20 or 40"))?;
            }
            _ => {
                c.brakes = match value {
                    1.0 => true,
                    0.0 => false,
                    v => return Err(format!("{v} is not 0 or 1")),
                }
            }
        }
        Ok(c)
    }
}

/// The throttle an action sets (clipped to -1..1).
#[inline(always)]
fn throttle_of(a: f64) -> f64 {
    (a + 1.0) * 0.5
}

/// The angle of attack an action sets, degrees.
#[inline(always)]
fn alpha_deg_of(a: f64) -> f64 {
    2.0 + 18.0 * a
}

/// The bank an action sets, degrees.
#[inline(always)]
fn bank_deg_of(a: f64) -> f64 {
    20.0 * a
}

/// The flaps an action sets, degrees: exactly 0, 20 or 40.
#[inline(always)]
fn flaps_deg_of(a: f64) -> f64 {
    if a < -1.0 / 3.0 {
        0.0
    } else if a <= 1.0 / 3.0 {
        20.0
    } else {
        40.0
    }
}

/// The flap setting of [`flaps_deg_of`]'s degrees.
#[inline(always)]
fn flaps_of(degrees: f64) -> Flaps {
    if degrees == 0.0 {
        Flaps::Up
    } else if degrees == 20.0 {
        Flaps::Deg20
    } else {
        Flaps::Deg40
    }
}

/// The observed flaps, `flaps.degrees() / 40.0`, without the division: the
/// degrees are exactly 0, 20 or 40, so the quotients are exactly 0, 0.5 and
/// 1 (the same bits; `lane_agent_is_the_per_aircraft_methods` compares
/// them with [`AgentModel::task_control_obs`]'s division).
#[inline(always)]
fn flaps_obs(flaps: Flaps) -> f64 {
    match flaps {
        Flaps::Up => 0.0,
        Flaps::Deg20 => 0.5,
        Flaps::Deg40 => 1.0,
    }
}

/// Palmer's controls from one aircraft's clipped actions: throttle,
/// alpha_deg, bank_deg, flaps_deg (control indices 0..4).
#[inline]
#[must_use]
fn palmer_controls(a: &[f64]) -> [(usize, f64); 4] {
    [
        (0, throttle_of(a[0])),
        (1, alpha_deg_of(a[1])),
        (2, bank_deg_of(a[2])),
        (3, flaps_deg_of(a[3])),
    ]
}

impl AgentModel for Palmer {
    const TASK_ACTIONS: usize = 4;
    const TASK_CONTROL_OBS: usize = 4;

    // `speed * 1.0` is `speed`, bit for bit.
    const GROUND_MPS_PER_SPEED: f64 = 1.0;

    #[inline(always)]
    fn task_kinematics(v: &[f64]) -> Kinematics {
        Kinematics {
            altitude_ft: v[3] * FT_PER_M,
            climb_ftps: v[6] * FT_PER_M,
            vx: v[4],
            vy: v[5],
        }
    }

    #[inline]
    fn task_control_obs(c: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&[c[0], c[1] / 20.0, c[2] / 20.0, c[3] / 40.0]);
    }

    #[inline]
    fn task_controls(a: &[f64]) -> ([(usize, f64); 5], usize) {
        let [p0, p1, p2, p3] = palmer_controls(a);
        ([p0, p1, p2, p3, (0, 0.0)], 4)
    }

    #[inline]
    fn task_apply(mut c: PalmerControls, a: &[f64]) -> PalmerControls {
        let [(_, throttle), (_, alpha_deg), (_, bank_deg), (_, flaps)] = palmer_controls(a);
        c.throttle = throttle;
        c.alpha_deg = alpha_deg;
        c.bank_deg = bank_deg;
        c.flaps = flaps_of(flaps);
        c
    }
}

/// A block's columns and controls, each lane the per-aircraft methods'
/// operations in the same order, the lanes together (the compiler may put
/// them in vector registers: every operation is correctly rounded, none is
/// fused).
impl LaneAgent for Palmer {
    const BLOCK_READS: bool = true;

    /// The state's columns are the block's own lanes (`vars` is `[vx, x,
    /// vy, y, vz, z]`), copied, every lane (those past `count` too).
    #[inline(always)]
    fn block_state_values(block: &Block<Self>, _count: usize, out: &mut [[f64; LANES]]) {
        let v = &block.vars;
        let columns = [block.time, v[1].0, v[3].0, v[5].0, v[0].0, v[2].0, v[4].0];
        for (o, c) in out.iter_mut().zip(&columns) {
            // Every lane: a copy of a fixed length.
            *o = *c;
        }
    }

    /// [`AgentModel::task_kinematics`]'s operations on whole lanes.
    #[inline(always)]
    fn block_kinematics(columns: &[[f64; LANES]], out: &mut [[f64; LANES]; 4]) {
        *out = [
            columns[3].map(|z| z * FT_PER_M),
            columns[6].map(|vz| vz * FT_PER_M),
            columns[4],
            columns[5],
        ];
    }

    #[inline(always)]
    fn block_control_obs(
        controls: &[PalmerControls; LANES],
        _count: usize,
        out: &mut [[f64; LANES]; MAX_CONTROL_OBS],
    ) {
        // Every lane (those past `count` hold controls too): the divisions
        // of the whole block together.
        for (l, c) in controls.iter().enumerate() {
            out[0][l] = c.throttle;
            out[1][l] = c.alpha_deg / 20.0;
            out[2][l] = c.bank_deg / 20.0;
            out[3][l] = flaps_obs(c.flaps);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(feature = "dis")]
    use crate::model::test_support::{lanes_against_frames, uniform_in_plus_minus_one};
    use fdm_core::message::ShortNumber;
    use fdm_core::model::Model;

    /// The observed flaps of every setting are the per-aircraft method's
    /// division, bit for bit (the agent tests' fleet members have no 40°
    /// flaps), in each lane of a block.
    #[test]
    fn observed_flaps_are_the_division() {
        for flaps in [Flaps::Up, Flaps::Deg20, Flaps::Deg40] {
            let c = PalmerControls {
                flaps,
                ..PalmerControls::default()
            };
            let mut values = [0.0; 5];
            Palmer::control_values(&c, &mut values);
            let mut want = [0.0; 4];
            Palmer::task_control_obs(&values, &mut want);
            assert_eq!(want[3].to_bits(), (flaps.degrees() / 40.0).to_bits());
            let mut out = [[f64::NAN; LANES]; MAX_CONTROL_OBS];
            Palmer::block_control_obs(&[c; LANES], LANES, &mut out);
            for lane in out[3] {
                assert_eq!(lane.to_bits(), want[3].to_bits(), "{flaps:?}");
            }
        }
    }

    /// A state with every field its own number (exact in binary): at
    /// 7.5 s, 1234.5 m north, 0.25 m east and 321.75 m up, flying 12 m/s
    /// north, 16 m/s east and 15 m/s up (a 3-4-5 triangle twice: 20 m/s
    /// horizontally, 25 m/s in all).
    fn hand_state() -> PalmerState {
        PalmerState {
            time_s: 7.5,
            position_m: nalgebra::Vector3::new(1234.5, -0.25, 321.75),
            velocity_mps: nalgebra::Vector3::new(12.0, -16.0, 15.0),
        }
    }

    /// Controls with every field off its default: throttle 75 %, alpha
    /// -3.5°, bank 12°, flaps 40°, brakes set.
    fn hand_controls() -> PalmerControls {
        PalmerControls {
            throttle: 0.75,
            alpha_deg: -3.5,
            bank_deg: 12.0,
            flaps: Flaps::Deg40,
            brakes: true,
        }
    }

    /// A recorded aircraft comes back as it was, even the tail area a
    /// study cannot set (the record is the aircraft itself), and a record
    /// `PalmerAircraft::validate` refuses is refused in its words, naming
    /// the first bad field: 0 kg (must be > 0), a negative parasite drag
    /// (must be >= 0), a NaN wing span (must be finite).
    #[test]
    fn a_recorded_aircraft_comes_back_and_bad_parameters_are_refused() {
        let mut aircraft = Palmer::aircraft_with(&[("mass_kg", 950.0), ("prop_b", -1.25)]).unwrap();
        aircraft.tail_area_m2 = 3.0;
        assert_ne!(aircraft, PalmerAircraft::cessna_172());
        let record = Palmer::aircraft_record(&aircraft);
        assert_eq!(record, aircraft);
        assert_eq!(Palmer::aircraft_from_record(record), Ok(aircraft));
        let bad = |edit: fn(&mut PalmerAircraft)| {
            let mut r = record;
            edit(&mut r);
            Palmer::aircraft_from_record(r)
        };
        assert_eq!(
            bad(|r| r.mass_kg = 0.0),
            Err("aircraft parameter `mass_kg` must be > 0, got 0".to_owned())
        );
        assert_eq!(
            bad(|r| r.cdp = -0.5),
            Err("aircraft parameter `cdp` must be >= 0, got -0.5".to_owned())
        );
        assert_eq!(
            bad(|r| {
                r.wing_span_m = f64::NAN;
                r.mass_kg = 0.0;
            }),
            Err("aircraft parameter `wing_span_m` must be finite, got NaN".to_owned())
        );
    }

    /// What a recording keeps of a state is the state half of fdm-core's
    /// fingerprint (the docs of `RunModel::state_fingerprint`), so a state a
    /// step on has another.
    #[test]
    fn the_recorded_fingerprint_is_the_states() {
        crate::model::test_support::recorded_fingerprint_is_the_states::<Palmer>(
            |s| fingerprint::Fingerprint::of_palmer(s).state,
            &[hand_state()],
        );
    }

    /// A fleet's offsets are metres, as Palmer's position is: 30.25 m
    /// north, 60.5 m west and 3.125 m down move an aircraft from (1000.5,
    /// -2000.25, 1500) m to (1030.75, -1939.75, 1496.875) m (every number
    /// exact in binary, so the sums are exact), and nothing else.
    #[test]
    fn an_offset_in_metres_moves_the_metres() {
        let (_, mut state) = Palmer::fleet_member(4);
        state.time_s = 7.5;
        state.position_m = nalgebra::Vector3::new(1000.5, -2000.25, 1500.0);
        let moved = Palmer::offset_state(&state, 30.25, 60.5, -3.125);
        assert_eq!(
            <[f64; 3]>::from(moved.position_m),
            [1030.75, -1939.75, 1496.875]
        );
        assert_eq!(
            PalmerState {
                position_m: state.position_m,
                ..moved
            },
            state
        );
    }

    /// The CSV's position and velocity are the state's metres, bit for bit
    /// (`METRES_PER_UNIT` 1): the view's `position_m` and `velocity_mps`.
    /// And its own columns, in `CSV_COLUMNS`' order, from numbers worked by
    /// hand: airspeed `sqrt(12² + 16² + 15²)` = 25 m/s exactly, the
    /// controls (flaps in degrees), climb angle `atan(15 / 20)` =
    /// 36.869897645844021°, climb rate 15 m/s, heading (from north toward
    /// west) `360° - atan(16 / 12)` = 306.86989764584402° (to 1e-12°: a few
    /// roundings of `atan` and the degree conversion).
    #[test]
    fn the_csvs_columns_are_the_views_metres_and_the_flight_data() {
        let state = hand_state();
        let controls = hand_controls();
        let view = Palmer::view(&Palmer::default_aircraft(), &controls, &state);
        assert_eq!(Palmer::METRES_PER_UNIT, 1.0);
        let bits = |v: [f64; 3]| v.map(f64::to_bits);
        let (p, v) = (
            Palmer::native_position(&state),
            Palmer::native_velocity(&state),
        );
        assert_eq!(bits(p), bits([1234.5, -0.25, 321.75]));
        assert_eq!(bits(v), bits([12.0, -16.0, 15.0]));
        assert_eq!(bits(p), bits(view.position_m.into()));
        assert_eq!(bits(v), bits(view.velocity_mps.into()));

        let mut row = Vec::new();
        Palmer::csv_values(&controls, &state, &mut row);
        assert_eq!(row.len(), Palmer::CSV_COLUMNS.len());
        let want = [
            25.0,
            0.75,
            -3.5,
            12.0,
            40.0,
            36.869_897_645_844_02,
            15.0,
            306.869_897_645_844,
        ];
        for ((name, got), want) in Palmer::CSV_COLUMNS.iter().zip(&row).zip(want) {
            assert!((got - want).abs() <= 1e-12, "{name}: {got} against {want}");
        }
        assert_eq!(Palmer::CSV_SPEED_COLUMN, Palmer::CSV_COLUMNS[0]);
    }

    /// The report's fields are the state's flight data and the controls as
    /// they are (flaps in degrees, the brakes), from the numbers of
    /// [`the_csvs_columns_are_the_views_metres_and_the_flight_data`] (to
    /// 1e-12°); the aircraft does not enter them.
    #[test]
    fn the_report_details_are_the_flight_data_and_the_controls() {
        let d = Palmer::details(&Palmer::default_aircraft(), &hand_controls(), &hand_state());
        assert_eq!(d.airspeed, 25.0);
        assert_eq!(
            d.controls,
            PalmerControlsReport {
                throttle: 0.75,
                alpha_deg: -3.5,
                bank_deg: 12.0,
                flaps_deg: 40.0,
                brakes: true,
            }
        );
        assert!(
            (d.climb_angle_deg - 36.869_897_645_844_02).abs() <= 1e-12,
            "{d:?}"
        );
        assert_eq!(d.climb_rate, 15.0);
        assert!(
            (d.heading_deg - 306.869_897_645_844).abs() <= 1e-12,
            "{d:?}"
        );
        let heavy = Palmer::aircraft_with(&[("mass_kg", 2000.0)]).unwrap();
        assert_eq!(Palmer::details(&heavy, &hand_controls(), &hand_state()), d);
    }

    /// The sample snapshot is what its docs say: 55.6 m/s (its details'
    /// airspeed is the snapshot's), 75 % throttle, 4° of attack, banked 5°,
    /// 20° of flaps, brakes off, airborne, on `CommonState::sample`.
    #[test]
    fn the_sample_snapshot_is_its_docs() {
        let s = PalmerDetails::sample_snapshot();
        assert_eq!(s.airspeed_mps, 55.6);
        assert_eq!(s.details.airspeed, s.airspeed_mps);
        assert_eq!(
            s.details.controls,
            PalmerControlsReport {
                throttle: 0.75,
                alpha_deg: 4.0,
                bank_deg: 5.0,
                flaps_deg: 20.0,
                brakes: false,
            }
        );
        assert_eq!(s.status, FlightStatus::Airborne);
        assert!(!s.stalling);
        assert_eq!(s.common, CommonState::sample());
    }

    /// The report's controls leave the brakes out of the JSON while they
    /// are off (so reports read as before the brakes), write `"brakes":
    /// true` while they are set, and read a report without them as off.
    #[test]
    fn the_reports_brakes_are_written_only_while_set() {
        let off = PalmerDetails::sample_snapshot().details.controls;
        let on = PalmerControlsReport {
            brakes: true,
            ..off
        };
        let json = |c: &PalmerControlsReport| serde_json::to_value(c).unwrap();
        let written = json(&off);
        assert_eq!(
            written,
            serde_json::json!({
                "throttle": 0.75,
                "alpha_deg": 4.0,
                "bank_deg": 5.0,
                "flaps_deg": 20.0,
            })
        );
        assert_eq!(json(&on)["brakes"], serde_json::Value::Bool(true));
        assert_eq!(json(&on).as_object().unwrap().len(), 5);
        let read: PalmerControlsReport = serde_json::from_value(written).unwrap();
        assert_eq!(read, off);
        assert_eq!(
            serde_json::from_value::<PalmerControlsReport>(json(&on)).unwrap(),
            on
        );
    }

    /// The summary's lines: airspeed to the millimetre per second, climb
    /// angle to a hundredth of a degree, climb rate, throttle in whole per
    /// cent, the angles and flaps as they are (`{}`), and `  BRAKES`
    /// (`brakes_note`) after the flaps while the brakes are set.
    #[test]
    fn the_summary_shows_the_details_and_the_brakes() {
        assert_eq!(brakes_note(true), "  BRAKES");
        assert_eq!(brakes_note(false), "");
        let mut d = PalmerDetails::sample_snapshot().details;
        let line = "airspeed  55.600 m/s  climb 3.10 deg, 2.900 m/s\n\
                    controls  throttle 75 %  alpha 4 deg  bank 5 deg  flaps 20 deg";
        assert_eq!(d.summary(), line);
        d.controls.brakes = true;
        assert_eq!(d.summary(), format!("{line}  BRAKES"));
    }

    /// A study file sets the controls by name in the ranges of `sim-cli
    /// palmer --throttle/--alpha/--bank` (0..1, -16..20°, -20..20°, the
    /// ends included); a value out of its range (or NaN) is refused in
    /// `in_range`'s words and leaves the controls as they were; another
    /// name is refused listing the names.
    #[test]
    fn a_study_sets_the_controls_by_name() {
        let mut c = Palmer::initial_controls();
        for (key, value) in [
            ("throttle", 1.0),
            ("throttle", 0.0),
            ("alpha_deg", -16.0),
            ("alpha_deg", 20.0),
            ("bank_deg", -20.0),
            ("bank_deg", 20.0),
            ("throttle", 0.25),
            ("alpha_deg", 7.5),
            ("bank_deg", -12.5),
        ] {
            Palmer::set_control(&mut c, key, value).unwrap_or_else(|e| panic!("{e}"));
        }
        let want = PalmerControls {
            throttle: 0.25,
            alpha_deg: 7.5,
            bank_deg: -12.5,
            ..Palmer::initial_controls()
        };
        assert_eq!(c, want);
        for (key, value, refusal) in [
            (
                "throttle",
                1.5,
                "throttle = 1.5: expected a number from 0 to 1",
            ),
            (
                "throttle",
                -0.25,
                "throttle = -0.25: expected a number from 0 to 1",
            ),
            (
                "alpha_deg",
                -16.5,
                "alpha_deg = -16.5: expected a number from -16 to 20",
            ),
            (
                "alpha_deg",
                20.5,
                "alpha_deg = 20.5: expected a number from -16 to 20",
            ),
            (
                "bank_deg",
                -20.5,
                "bank_deg = -20.5: expected a number from -20 to 20",
            ),
            (
                "bank_deg",
                f64::NAN,
                "bank_deg = NaN: expected a number from -20 to 20",
            ),
        ] {
            assert_eq!(
                Palmer::set_control(&mut c, key, value),
                Err(refusal.to_owned())
            );
        }
        assert_eq!(
            Palmer::set_control(&mut c, "flaps", 20.0),
            Err(
                "unknown control `flaps`; expected one of throttle, alpha_deg, bank_deg, \
                 flaps_deg, brakes"
                    .to_owned()
            )
        );
        assert_eq!(c, want);
    }

    /// The flaps by name take exactly the three notches of `sim-cli palmer
    /// --flaps` (0, 20, 40 degrees) and the brakes exactly 0 (off) or 1
    /// (on), each setting its own field only; anything else (between two
    /// notches, beyond them, negative, NaN, infinite) is refused naming the
    /// key and the settings, and leaves the controls as they were.
    #[test]
    fn a_study_sets_the_flaps_and_brakes_by_name() {
        let start = Palmer::initial_controls();
        assert_eq!((start.flaps, start.brakes), (Flaps::Up, false));
        for (degrees, flaps) in [(40.0, Flaps::Deg40), (20.0, Flaps::Deg20), (0.0, Flaps::Up)] {
            // From each of the others, so the setting is the value's own.
            for from in [Flaps::Up, Flaps::Deg20, Flaps::Deg40] {
                let mut c = PalmerControls {
                    flaps: from,
                    ..start
                };
                Palmer::set_control(&mut c, "flaps_deg", degrees).unwrap();
                assert_eq!(
                    c,
                    PalmerControls { flaps, ..start },
                    "{degrees} from {from:?}"
                );
            }
        }
        for (value, brakes) in [(1.0, true), (0.0, false)] {
            for from in [false, true] {
                let mut c = PalmerControls {
                    brakes: from,
                    ..start
                };
                Palmer::set_control(&mut c, "brakes", value).unwrap();
                assert_eq!(c, PalmerControls { brakes, ..start }, "{value} from {from}");
            }
        }
        let set = PalmerControls {
            flaps: Flaps::Deg20,
            brakes: true,
            ..start
        };
        for value in [
            10.0,
            19.5,
            20.5,
            30.0,
            60.0,
            1.0,
            -20.0,
            -0.5,
            f64::NAN,
            f64::INFINITY,
        ] {
            let mut c = set;
            assert_eq!(
                Palmer::set_control(&mut c, "flaps_deg", value),
                Err(format!(
                    "flaps_deg = {}: expected 0, 20 or 40",
                    ShortNumber(value)
                ))
            );
            assert_eq!(c, set);
        }
        // The words, written out (as `sim-cli palmer --flaps 10` would see them).
        let mut c = set;
        assert_eq!(
            Palmer::set_control(&mut c, "flaps_deg", 10.0),
            Err("flaps_deg = 10: expected 0, 20 or 40".to_owned())
        );
        assert_eq!(
            Palmer::set_control(&mut c, "flaps_deg", f64::NAN),
            Err("flaps_deg = NaN: expected 0, 20 or 40".to_owned())
        );
        for value in [2.0, 0.5, -0.5, -1.0, 20.0, f64::NAN] {
            let mut c = set;
            assert_eq!(
                Palmer::set_control(&mut c, "brakes", value),
                Err(format!("brakes = {}: expected 0 or 1", ShortNumber(value)))
            );
            assert_eq!(c, set);
        }
        assert_eq!(
            Palmer::set_control(&mut c, "brakes", -0.5),
            Err("brakes = -0.5: expected 0 or 1".to_owned())
        );
    }

    /// `CONTROL_KEYS` is exactly what `set_control` takes: each key, in
    /// order, sets its own field (each value another than the start's, the
    /// fields by their serialized names: `flaps` for `flaps_deg`), and a
    /// name that is not one is refused listing them.
    #[test]
    fn the_control_keys_are_what_set_control_takes() {
        let values = [
            ("throttle", 0.5),
            ("alpha_deg", 3.0),
            ("bank_deg", -10.0),
            ("flaps_deg", 40.0),
            ("brakes", 1.0),
        ];
        let all = crate::model::test_support::each_control_key_sets_its_own_field::<Palmer>(
            &values,
            |key| {
                if key == "flaps_deg" {
                    "flaps"
                } else {
                    key
                }
            },
        );
        assert_eq!(
            all,
            PalmerControls {
                throttle: 0.5,
                alpha_deg: 3.0,
                bank_deg: -10.0,
                flaps: Flaps::Deg40,
                brakes: true,
            }
        );
        for key in ["Throttle", "flaps_degrees", "brake", ""] {
            assert_eq!(
                Palmer::set_control(&mut { all }, key, 0.0),
                Err(unknown_key("control", key, Palmer::CONTROL_KEYS))
            );
        }
    }

    /// A study file's aircraft parameters: each of the fifteen names sets
    /// its own field of the Cessna 172 (each value another than the
    /// Cessna's), in order (the last value of a name counts, and only the
    /// result is checked); no parameters give the Cessna; a result
    /// `PalmerAircraft::validate` refuses is refused in its words; another
    /// name (the tail area, which the equations do not use, is not one) is
    /// refused listing the names.
    #[test]
    fn a_study_sets_the_aircraft_by_name() {
        let values = [
            ("wing_area_m2", 17.5),
            ("wing_span_m", 11.25),
            ("cl_slope0_per_deg", 0.09),
            ("cl0", 0.2),
            ("cl_slope1_per_deg", -0.125),
            ("cl1", 3.0),
            ("alpha_cl_max_deg", 15.0),
            ("cdp", 0.03),
            ("eff", 0.8),
            ("mass_kg", 1000.0),
            ("engine_power_w", 120_000.0),
            ("engine_rps", 42.0),
            ("prop_diameter_m", 1.8),
            ("prop_a", 1.9),
            ("prop_b", -1.25),
        ];
        let want = PalmerAircraft {
            wing_area_m2: 17.5,
            wing_span_m: 11.25,
            tail_area_m2: 2.0,
            cl_slope0_per_deg: 0.09,
            cl0: 0.2,
            cl_slope1_per_deg: -0.125,
            cl1: 3.0,
            alpha_cl_max_deg: 15.0,
            cdp: 0.03,
            eff: 0.8,
            mass_kg: 1000.0,
            engine_power_w: 120_000.0,
            engine_rps: 42.0,
            prop_diameter_m: 1.8,
            prop_a: 1.9,
            prop_b: -1.25,
        };
        assert_eq!(Palmer::aircraft_with(&values), Ok(want));
        assert_eq!(Palmer::AIRCRAFT_KEYS, values.map(|(key, _)| key).as_slice());
        // Each name alone changes its own field only (the fields by their
        // serialized names, which are the keys).
        let cessna = PalmerAircraft::cessna_172();
        let fields = |a: &PalmerAircraft| match serde_json::to_value(a).unwrap() {
            serde_json::Value::Object(map) => map,
            other => panic!("{other}"),
        };
        let original = fields(&cessna);
        for (key, value) in values {
            let a = fields(&Palmer::aircraft_with(&[(key, value)]).unwrap());
            let changed: Vec<&str> = original
                .iter()
                .filter(|(k, v)| a[k.as_str()] != **v)
                .map(|(k, _)| k.as_str())
                .collect();
            assert_eq!(changed, [key]);
            assert_eq!(a[key], serde_json::json!(value), "{key}");
        }
        assert_eq!(Palmer::aircraft_with(&[]), Ok(cessna));
        assert_eq!(
            Palmer::aircraft_with(&[("mass_kg", -1.0), ("mass_kg", 900.0)]).map(|a| a.mass_kg),
            Ok(900.0)
        );
        assert_eq!(
            Palmer::aircraft_with(&[("eff", 0.0)]),
            Err("aircraft parameter `eff` must be > 0, got 0".to_owned())
        );
        assert_eq!(
            Palmer::aircraft_with(&[("tail_area_m2", 2.5)]),
            Err(format!(
                "unknown aircraft parameter `tail_area_m2`; expected one of {}",
                values.map(|(key, _)| key).join(", ")
            ))
        );
    }

    /// The cheap reads of a state in flight (its time past 0) are the
    /// view's, bit for bit.
    #[test]
    fn the_cheap_reads_of_a_flight_are_the_views() {
        crate::model::test_support::cheap_reads_are_the_views::<Palmer>();
        assert_eq!(Palmer::time_s(&hand_state()), 7.5);
        assert_eq!(Palmer::velocity_mps(&hand_state()), [12.0, -16.0, 15.0]);
    }

    /// `sim-cli palmer`'s start: the table's number options take the
    /// documented ranges (throttle 0..1, alpha -16..20°, bank -20..20°,
    /// the ends included), and its defaults (0, 0, 0, flaps 0, no brakes)
    /// give the model's own start; given values become the controls as they
    /// are (flaps by degrees, the brakes flag), and a flap setting the
    /// model has not is refused.
    #[test]
    fn the_pilots_start_options_and_controls() {
        use crate::model::pilot::OptionKind;
        let mut ranges = Vec::new();
        let defaults: Vec<OptionValue> = Palmer::START_OPTIONS
            .iter()
            .map(|o| match o.kind {
                OptionKind::Number { range, default, .. } => {
                    ranges.push((o.long, range.low, range.high));
                    for end in [range.low, range.high] {
                        assert_eq!(range.parse(&end.to_string()), Ok(end), "--{}", o.long);
                    }
                    OptionValue::Number(range.parse(default.unwrap()).unwrap())
                }
                OptionKind::Choice {
                    choices, default, ..
                } => OptionValue::Choice(choices.parse(default).unwrap()),
                OptionKind::Flag => OptionValue::Flag(false),
            })
            .collect();
        assert_eq!(
            ranges,
            [
                ("throttle", 0.0, 1.0),
                ("alpha", -16.0, 20.0),
                ("bank", -20.0, 20.0)
            ]
        );
        assert_eq!(
            Palmer::start_controls(&defaults),
            Ok(Palmer::initial_controls())
        );
        let given = |flaps: &'static str| {
            Palmer::start_controls(&[
                OptionValue::Number(0.75),
                OptionValue::Number(-3.5),
                OptionValue::Number(12.0),
                OptionValue::Choice(flaps),
                OptionValue::Flag(true),
            ])
        };
        assert_eq!(given("40"), Ok(hand_controls()));
        assert_eq!(given("20").map(|c| c.flaps), Ok(Flaps::Deg20));
        assert_eq!(
            given("30"),
            Err("--flaps 30: not a flap setting (0, 20 or 40)".to_owned())
        );
    }

    /// The HUD's controls line: throttle in whole per cent (3 wide), alpha
    /// and bank signed to a tenth (5 wide, what shows as zero as `+0.0`:
    /// `tenths`), flaps in degrees, and `  BRAKES` while the brakes are set;
    /// the model's start (with an alpha of -0.04°, shown as `+0.0`), the
    /// sample snapshot, and full throttle banked -12.5° with the brakes.
    #[test]
    fn the_controls_line_shows_the_controls() {
        let mut start = Palmer::initial_controls();
        start.alpha_deg = -0.04;
        let details = |c: &PalmerControls| {
            Palmer::details(&Palmer::default_aircraft(), c, &Palmer::initial_state())
        };
        assert_eq!(
            details(&start).controls_line(),
            "THROTTLE   0 %   ALPHA  +0.0 deg   BANK  +0.0 deg   FLAPS 0 deg"
        );
        let mut sample = PalmerDetails::sample_snapshot().details;
        assert_eq!(
            sample.controls_line(),
            "THROTTLE  75 %   ALPHA  +4.0 deg   BANK  +5.0 deg   FLAPS 20 deg"
        );
        sample.controls.throttle = 1.0;
        sample.controls.bank_deg = -12.5;
        sample.controls.brakes = true;
        assert_eq!(
            sample.controls_line(),
            "THROTTLE 100 %   ALPHA  +4.0 deg   BANK -12.5 deg   FLAPS 20 deg  BRAKES"
        );
    }

    /// The state's columns are `STATE_FIELDS` in order (time, position,
    /// velocity), the state's numbers bit for bit; the controls' columns
    /// are `CONTROL_FIELDS` in order (flaps in degrees, brakes 1 or 0),
    /// with the ranges of `sim-cli palmer`'s options (throttle 0..1, alpha
    /// -16..20°, bank -20..20°), flaps 0..40° and brakes 0..1.
    #[test]
    fn the_columns_are_the_state_and_the_controls() {
        assert_eq!(
            Palmer::STATE_FIELDS,
            ["time_s", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"]
        );
        let mut values = [f64::NAN; 7];
        Palmer::state_values(&hand_state(), &mut values);
        assert_eq!(
            values.map(f64::to_bits),
            [7.5, 1234.5, -0.25, 321.75, 12.0, -16.0, 15.0].map(f64::to_bits)
        );
        assert_eq!(
            Palmer::CONTROL_FIELDS,
            [
                ("throttle", 0.0, 1.0),
                ("alpha_deg", -16.0, 20.0),
                ("bank_deg", -20.0, 20.0),
                ("flaps_deg", 0.0, 40.0),
                ("brakes", 0.0, 1.0),
            ]
        );
        let mut values = [f64::NAN; 5];
        Palmer::control_values(&hand_controls(), &mut values);
        assert_eq!(values, [0.75, -3.5, 12.0, 40.0, 1.0]);
        let c = PalmerControls {
            brakes: false,
            flaps: Flaps::Deg20,
            ..hand_controls()
        };
        Palmer::control_values(&c, &mut values);
        assert_eq!(values, [0.75, -3.5, 12.0, 20.0, 0.0]);
    }

    /// A control set by its column's index changes that control only:
    /// the throttle, alpha and bank as given, the flaps for 0, 20 and 40
    /// (another number in their range refused), the brakes for 1 and 0
    /// (another number refused).
    #[test]
    fn a_control_is_set_by_its_columns_index() {
        let start = hand_controls();
        let set = |index: usize, value: f64| Palmer::with_control(start, index, value);
        let with = |edit: fn(&mut PalmerControls)| {
            let mut c = start;
            edit(&mut c);
            Ok(c)
        };
        assert_eq!(set(0, 0.25), with(|c| c.throttle = 0.25));
        assert_eq!(set(1, 7.5), with(|c| c.alpha_deg = 7.5));
        assert_eq!(set(2, -12.5), with(|c| c.bank_deg = -12.5));
        assert_eq!(set(3, 0.0), with(|c| c.flaps = Flaps::Up));
        assert_eq!(set(3, 20.0), with(|c| c.flaps = Flaps::Deg20));
        assert_eq!(set(3, 40.0), Ok(start));
        assert_eq!(set(3, 30.0), Err("30 is not 0, 20 or 40".to_owned()));
        assert_eq!(set(4, 0.0), with(|c| c.brakes = false));
        assert_eq!(
            Palmer::with_control(Palmer::initial_controls(), 4, 1.0).map(|c| c.brakes),
            Ok(true)
        );
        assert_eq!(set(4, 0.5), Err("0.5 is not 0 or 1".to_owned()));
    }

    /// The tasks' actions (`afit_fdm.gym`, its oracle
    /// `test_task_kernel.py`): throttle `(a + 1) / 2`, alpha `2 + 18 a`
    /// degrees, bank `20 a` degrees, flaps 0° below -1/3, 20° from -1/3 to
    /// 1/3 (both included), 40° above (and for NaN, which no comparison
    /// holds for); the controls set are indices 0..4, four of them. The
    /// numbers are exact in binary (and so the operations).
    #[test]
    fn the_tasks_actions_set_throttle_alpha_bank_and_flaps() {
        for (a, throttle, alpha, bank) in [
            (-1.0, 0.0, -16.0, -20.0),
            (-0.5, 0.25, -7.0, -10.0),
            (0.0, 0.5, 2.0, 0.0),
            (0.5, 0.75, 11.0, 10.0),
            (1.0, 1.0, 20.0, 20.0),
        ] {
            let (list, count) = Palmer::task_controls(&[a, a, a, 0.0]);
            assert_eq!(count, 4);
            assert_eq!(
                list[..4],
                [(0, throttle), (1, alpha), (2, bank), (3, 20.0)],
                "{a}"
            );
        }
        let third = 1.0_f64 / 3.0;
        for (a, flaps) in [
            (-1.0, 0.0),
            (-0.5, 0.0),
            ((-third).next_down(), 0.0),
            (-third, 20.0),
            (0.0, 20.0),
            (third, 20.0),
            (third.next_up(), 40.0),
            (0.5, 40.0),
            (1.0, 40.0),
            (f64::NAN, 40.0),
        ] {
            let (list, _) = Palmer::task_controls(&[0.0, 0.0, 0.0, a]);
            assert_eq!(list[3], (3, flaps), "{a}");
        }
    }

    /// `task_apply` sets the throttle, alpha, bank and flap setting of the
    /// actions (as [`the_tasks_actions_set_throttle_alpha_bank_and_flaps`]
    /// worked them) and keeps the brakes; the observed controls of those
    /// controls are throttle, alpha / 20, bank / 20 and flaps / 40: for
    /// actions (0.5, 0.5, -0.5, a), a 1, 0 or -1, the controls 0.75, 11°,
    /// -10°, flaps 40°, 20° or 0°, observed as 0.75, 0.55 (11 / 20
    /// correctly rounded is the double nearest 0.55), -0.5, 1, 0.5 or 0.
    #[test]
    fn the_tasks_apply_and_observe_the_controls() {
        let start = hand_controls();
        for (a3, flaps, observed) in [
            (1.0, Flaps::Deg40, 1.0),
            (0.0, Flaps::Deg20, 0.5),
            (-1.0, Flaps::Up, 0.0),
        ] {
            let got = Palmer::task_apply(start, &[0.5, 0.5, -0.5, a3]);
            assert_eq!(
                got,
                PalmerControls {
                    throttle: 0.75,
                    alpha_deg: 11.0,
                    bank_deg: -10.0,
                    flaps,
                    brakes: true,
                },
                "{a3}"
            );
            let mut values = [0.0; 5];
            Palmer::control_values(&got, &mut values);
            let mut obs = [f64::NAN; 4];
            Palmer::task_control_obs(&values, &mut obs);
            assert_eq!(obs, [0.75, 0.55, -0.5, observed], "{a3}");
        }
    }

    /// States for the rough DIS frames: velocities in every direction
    /// (up to 60 m/s a component; every seventh with no west component,
    /// flying north or south, every eleventh level, every thirteenth
    /// straight up or down), none within 5° of the vertical, so that the
    /// rough matrix is within the documented 1e-12 of the view's even
    /// through the Euler angles' round trip.
    #[cfg(feature = "dis")]
    fn rough_states(n: usize) -> Vec<Option<PalmerState>> {
        let mut next = uniform_in_plus_minus_one();
        (0..n)
            .map(|i| {
                let mut v = nalgebra::Vector3::new(next(), next(), next()) * 60.0;
                if i % 7 == 0 {
                    v.y = 0.0;
                }
                if i % 11 == 0 {
                    v.z = 0.0;
                }
                if i % 13 == 0 {
                    v.x = 0.0;
                    v.y = 0.0;
                } else if v.z.abs() > 10.0 * v.x.abs().max(v.y.abs()) {
                    v.z *= 0.05;
                }
                Some(PalmerState {
                    time_s: i as f64 / 30.0,
                    position_m: nalgebra::Vector3::new(i as f64 * 1.7 + 3.0, -3.3 * next(), 500.0),
                    velocity_mps: v,
                })
            })
            .collect()
    }

    /// A state at `velocity_mps` (time and position arbitrary).
    #[cfg(feature = "dis")]
    fn moving(velocity_mps: [f64; 3]) -> Option<PalmerState> {
        Some(PalmerState {
            time_s: 12.5,
            position_m: nalgebra::Vector3::new(-40.0, 75.5, 321.0),
            velocity_mps: nalgebra::Vector3::from(velocity_mps),
        })
    }

    /// The velocity of `speed` m/s climbing `climb_deg` on the compass
    /// track `track_deg` (the model's axes: x north, y west, z up).
    #[cfg(feature = "dis")]
    fn flying(speed: f64, climb_deg: f64, track_deg: f64) -> [f64; 3] {
        let (climb, track) = (climb_deg.to_radians(), track_deg.to_radians());
        [
            speed * climb.cos() * track.cos(),
            -speed * climb.cos() * track.sin(),
            speed * climb.sin(),
        ]
    }

    /// States with no rough frame by `palmer_rough`'s documentation
    /// whatever the controls: no state, a time or a position not finite,
    /// velocities not finite, out of the range 1e-100 to 1e100 m/s
    /// (horizontal or vertical).
    #[cfg(feature = "dis")]
    fn no_rough() -> Vec<Option<PalmerState>> {
        let placed = |time_s: f64, position_m: [f64; 3]| {
            moving([40.0, 0.0, 3.0]).map(|s| PalmerState {
                time_s,
                position_m: position_m.into(),
                ..s
            })
        };
        vec![
            None,
            placed(f64::NAN, [-40.0, 75.5, 321.0]),
            placed(f64::INFINITY, [-40.0, 75.5, 321.0]),
            placed(12.5, [f64::NAN, 75.5, 321.0]),
            placed(12.5, [-40.0, f64::NEG_INFINITY, 321.0]),
            placed(12.5, [-40.0, 75.5, f64::NAN]),
            moving([f64::NAN, 1.0, 1.0]),
            moving([1.0, f64::INFINITY, 1.0]),
            moving([1.0, 1.0, f64::NEG_INFINITY]),
            moving([1e-101, 0.0, 5.0]),
            moving([0.0, -1e-101, 5.0]),
            moving([5.0, 0.0, 1e-101]),
            moving([1e100, 0.0, 0.0]),
            moving([0.0, -1e100, 0.0]),
            moving([40.0, 0.0, -1e100]),
        ]
    }

    /// Aircraft `index` (a wings-level one of the fleet) with its nose
    /// `off_deg` from the vertical: climbing `90° - alpha - off_deg` on the
    /// track 30°, so that the nose's two horizontal components are both
    /// positive, `cos(pitch)² = sin(off)²` (0.03°: 2.7e-7, below the
    /// documented 1e-6, no frame; 0.1°: 3.0e-6, a frame).
    #[cfg(feature = "dis")]
    fn steep(index: usize, off_deg: f64) -> Option<PalmerState> {
        let (controls, _) = Palmer::fleet_member(index);
        assert_eq!(controls.bank_deg, 0.0, "aircraft {index}");
        moving(flying(50.0, 90.0 - controls.alpha_deg - off_deg, 30.0))
    }

    /// `FleetModel::dis_rough` (`palmer_rough`): aircraft `first + k` has
    /// the view's time, position and velocity bit for bit and the view's
    /// `attitude.body_to_ned()` within 1e-12 in every element (its docs:
    /// the same matrix up to about 1e-12 with the Euler round trip; these
    /// states stay 5° from the vertical), under the controls of
    /// `fleet_member(first + k)` (first 3, so that the aircraft index is
    /// not the slice's), over velocities in every direction, level,
    /// vertical and at rest, and at the range's ends (1e-100 and 9e99
    /// m/s), and 0.1° from the vertical; none for an aircraft without a
    /// state, or past the documented limits (`no_rough`, 5 of every 16
    /// aircraft, so in every group of eight), or 0.03° from the vertical.
    #[cfg(feature = "dis")]
    #[test]
    fn the_rough_frames_are_the_views() {
        let aircraft = Palmer::default_aircraft();
        let first = 3;
        let mut states = rough_states(300);
        for (i, s) in no_rough()
            .into_iter()
            .cycle()
            .take(300 / 16 * 5)
            .enumerate()
        {
            states[i / 5 * 16 + i % 5 * 3] = s;
        }
        for (i, v) in [
            [0.0; 3],
            [1e-100, 0.0, 0.0],
            [0.0, -1e-100, 1e-100],
            [9e99, 0.0, -9e99],
            [0.0, 0.0, 20.0],
            [0.0, 0.0, -20.0],
        ]
        .into_iter()
        .enumerate()
        {
            states[1 + 16 * i] = moving(v);
        }
        // Aircraft 10 and 94 (first + 7 and first + 91) are wings level.
        states[7] = steep(first + 7, 0.03);
        states[91] = steep(first + 91, 0.1);
        let mut out = vec![None; states.len()];
        Palmer::dis_rough(first, &states, &mut out);
        let mut made = 0;
        for (i, (s, r)) in states.iter().zip(&out).enumerate() {
            // The documented limits, independently of the code's form.
            let at_limits = |m: f64| m == 0.0 || (1e-100..1e100).contains(&m);
            let Some(s) = s.filter(|s| {
                let v = s.velocity_mps;
                s.time_s.is_finite()
                    && s.position_m.iter().all(|c| c.is_finite())
                    && v.iter().all(|c| c.is_finite())
                    && at_limits(v.z.abs())
                    && at_limits(v.x.abs().max(v.y.abs()))
            }) else {
                assert!(r.is_none(), "aircraft {i}: {r:?}");
                continue;
            };
            let view = Palmer::view(&aircraft, &Palmer::fleet_member(first + i).0, &s);
            let want = view.attitude.body_to_ned();
            let cos_pitch_sq = want[(0, 0)].powi(2) + want[(1, 0)].powi(2);
            let Some(r) = r.filter(|_| cos_pitch_sq >= 1e-6) else {
                assert!(r.is_none() && cos_pitch_sq < 1e-6, "aircraft {i}: {r:?}");
                continue;
            };
            assert_eq!(r.time_s.to_bits(), view.time_s.to_bits(), "aircraft {i}");
            let bits = |v: nalgebra::Vector3<f64>| v.map(f64::to_bits);
            assert_eq!(bits(r.position_m), bits(view.position_m), "aircraft {i}");
            assert_eq!(
                bits(r.velocity_mps),
                bits(view.velocity_mps),
                "aircraft {i}"
            );
            let worst = (r.body_to_ned - want).abs().max();
            assert!(
                worst <= 1e-12,
                "aircraft {i}: {worst:e}\n{}{want}",
                r.body_to_ned
            );
            made += 1;
        }
        assert_eq!(made, 300 - 300 / 16 * 5 - 1);
    }

    /// `palmer_rough` from numbers worked by hand. Palmer's state is in
    /// metres and seconds already (`METRES_PER_UNIT` 1), so the frame's
    /// time, position and velocity are the state's bits. Its matrix is
    /// `Rz(track) · Ry(climb) · Rx(bank) · Ry(alpha)` (north-east-down,
    /// body x forward, y right): with the fleet's controls of aircraft 10
    /// (alpha 2°, bank 0), flying north at 40 m/s climbing 30 m/s (climb
    /// atan(3/4)) the nose (the first column) is `(cos θ, 0, -sin θ)`, θ
    /// = climb + 2°, so `cos θ = 0.8 cos 2° - 0.6 sin 2°` and `sin θ = 0.6
    /// cos 2° + 0.8 sin 2°`; straight up (climb 90°) it is over the top,
    /// `(-sin 2°, 0, -cos 2°)`; with those of aircraft 0 (alpha 2°, bank
    /// -10°) flying east level the nose is `(-sin b sin a, cos a, -cos b
    /// sin a)` and the right wing (the second column) `(-cos b, 0, sin b)`,
    /// up, as the bank is to the left; at rest (track north, climb 0,
    /// aircraft 3: alpha 5°, bank -7°) the nose is `(cos a, sin b sin a,
    /// -cos b sin a)`. To 1e-14: a dozen roundings of numbers below 1
    /// (1.1e-16 each) and sines within an ulp or two of `std`'s.
    #[cfg(feature = "dis")]
    #[test]
    fn the_rough_frames_by_hand() {
        let rough = |index: usize, velocity: [f64; 3]| {
            let mut out = [None];
            palmer_rough(index, &[moving(velocity)], &mut out);
            out[0]
        };
        let close = |got: nalgebra::Vector3<f64>, want: [f64; 3]| {
            let worst = got
                .iter()
                .zip(want)
                .map(|(g, w)| (g - w).abs())
                .fold(0.0, f64::max);
            assert!(worst <= 1e-14, "{got} against {want:?}");
        };
        assert_eq!(Palmer::fleet_member(10).0.alpha_deg, 2.0);
        assert_eq!(Palmer::fleet_member(10).0.bank_deg, 0.0);
        assert_eq!(Palmer::fleet_member(0).0.bank_deg, -10.0);
        assert_eq!(Palmer::fleet_member(3).0.alpha_deg, 5.0);
        assert_eq!(Palmer::fleet_member(3).0.bank_deg, -7.0);
        let (sa, ca) = 2f64.to_radians().sin_cos();

        let r = rough(10, [40.0, 0.0, 30.0]).expect("a rough frame");
        assert_eq!(r.time_s.to_bits(), 12.5f64.to_bits());
        assert_eq!(<[f64; 3]>::from(r.position_m), [-40.0, 75.5, 321.0]);
        assert_eq!(<[f64; 3]>::from(r.velocity_mps), [40.0, 0.0, 30.0]);
        close(
            r.body_to_ned.column(0).into_owned(),
            [0.8 * ca - 0.6 * sa, 0.0, -(0.6 * ca + 0.8 * sa)],
        );

        let r = rough(10, [0.0, 0.0, 20.0]).expect("a rough frame");
        close(r.body_to_ned.column(0).into_owned(), [-sa, 0.0, -ca]);

        let (sb, cb) = (-10f64).to_radians().sin_cos();
        let r = rough(0, [0.0, -50.0, 0.0]).expect("a rough frame");
        close(
            r.body_to_ned.column(0).into_owned(),
            [-sb * sa, ca, -cb * sa],
        );
        close(r.body_to_ned.column(1).into_owned(), [-cb, 0.0, sb]);

        let (sa5, ca5) = 5f64.to_radians().sin_cos();
        let (sb7, cb7) = (-7f64).to_radians().sin_cos();
        let r = rough(3, [0.0; 3]).expect("a rough frame");
        close(
            r.body_to_ned.column(0).into_owned(),
            [ca5, sb7 * sa5, -cb7 * sa5],
        );
    }

    /// `FleetModel::dis_rough_lanes` (`palmer_rough_lanes`) is
    /// `palmer_rough` lane by lane, bit for bit (its docs), a lane without a
    /// rough frame not `ok`: groups of eight from `first` 0 and past it
    /// (each its own controls), groups with every state of `no_rough` and
    /// ones flying at the range's ends, level, vertical and at rest, the
    /// wings-level aircraft 10 and 31 (whose zero bank takes the lanes' own
    /// sine and cosine) 0.03° and 0.1° from the vertical, and a last group
    /// of fewer than eight, whose lanes past it are not `ok`.
    #[cfg(feature = "dis")]
    #[test]
    fn the_rough_lanes_are_the_rough_frames() {
        const L: usize = fdm_dis::ROUGH_LANES;
        let mut states = rough_states(5 * L + 5);
        let none = no_rough();
        states.splice(L + 3..L + 3 + none.len(), none);
        // After the states of `no_rough` (from the second group into the
        // fourth).
        states.splice(
            4 * L..4 * L + 5,
            [
                [0.0; 3],
                [1e-100, 0.0, 0.0],
                [9e99, 0.0, -9e99],
                [0.0, 0.0, 20.0],
                [50.0, 0.0, 0.0],
            ]
            .map(moving),
        );
        states[10] = steep(10, 0.03);
        states[31] = steep(31, 0.1);
        let mut want = vec![None; states.len()];
        palmer_rough(0, &states, &mut want);
        let (made, none) = lanes_against_frames::<Palmer>(&states, &want);
        let no = no_rough().len() + 1;
        assert_eq!((made, none), (states.len() - no, no));
    }
}
