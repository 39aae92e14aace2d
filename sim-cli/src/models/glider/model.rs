//! The glider's model: parameters, state, controls, the step written once
//! over `fdm_core::real`'s number type, the `Model` and `LaneModel` impls
//! and its fleet kernel. One source for two users: `sim-cli glider` (this
//! crate, behind the `glider` feature) and the example
//! `fdm-ecs/examples/third_model.rs`, which includes this file as its model
//! (so the model the example and its test check is the one the CLI flies).
//! It names nothing of `sim-cli`: only `fdm-core`, `fdm-fleet`, nalgebra and
//! serde.

use fdm_core::geodesy::Attitude;
use fdm_core::model::{FlightView, Model, ScriptAction};
use fdm_core::real::{F64s, LaneMask, LaneModel, Maths, Real, V3};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s².
const G_MPS2: f64 = 9.80665;

/// The glider's parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GliderAircraft {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Wing area, m².
    pub wing_area_m2: f64,
    /// Zero-lift drag coefficient.
    pub cd0: f64,
    /// Induced drag factor: `CD = cd0 + k·CL²`.
    pub induced_k: f64,
    /// Air density, kg/m³ (constant: a low-altitude glider).
    pub air_density_kgpm3: f64,
}

/// The glider's state: time, position and velocity in the shared earth frame
/// (x north, y west, z up), SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GliderState {
    /// Simulated time, s.
    pub time_s: f64,
    /// Position, m.
    pub position_m: Vector3<f64>,
    /// Velocity, m/s.
    pub velocity_mps: Vector3<f64>,
}

/// The glider's controls.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GliderControls {
    /// Lift coefficient, 0..=1.4.
    pub lift_coefficient: f64,
    /// Bank, degrees, right positive, within ±45.
    pub bank_deg: f64,
}

/// The glider's key presses and script actions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GliderAction {
    /// Lift coefficient +0.05.
    PitchUp,
    /// Lift coefficient −0.05.
    PitchDown,
    /// Bank 5° further left.
    BankLeft,
    /// Bank 5° further right.
    BankRight,
}

impl ScriptAction for GliderAction {
    const ALL: &'static [Self] = &[
        Self::PitchUp,
        Self::PitchDown,
        Self::BankLeft,
        Self::BankRight,
    ];
    const NAMES: &'static [&'static str] = &["pitch-up", "pitch-down", "bank-left", "bank-right"];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Why the glider refused to step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GliderError {
    /// `dt` is not a finite positive number.
    InvalidTimeStep,
    /// A number of the input or the result is not finite.
    NonFinite,
}

impl std::fmt::Display for GliderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::InvalidTimeStep => "the time step is not a finite positive number",
            Self::NonFinite => "a number is not finite",
        })
    }
}

/// The glider model.
#[derive(Debug, Clone, Copy, Default)]
pub struct Glider;

impl Model for Glider {
    const NAME: &'static str = "glider";
    const TITLE: &'static str = "Point-mass glider";

    type Aircraft = GliderAircraft;
    type State = GliderState;
    type Controls = GliderControls;
    type Action = GliderAction;
    type TimeStep = f64;
    type StepError = GliderError;

    fn default_aircraft() -> GliderAircraft {
        GliderAircraft {
            mass_kg: 400.0,
            wing_area_m2: 11.0,
            cd0: 0.012,
            induced_k: 0.02,
            air_density_kgpm3: 1.2,
        }
    }

    fn initial_controls() -> GliderControls {
        GliderControls {
            lift_coefficient: 0.6,
            bank_deg: 0.0,
        }
    }

    fn initial_state() -> GliderState {
        GliderState {
            time_s: 0.0,
            position_m: Vector3::new(0.0, 300.0, 600.0),
            velocity_mps: Vector3::new(30.0, 0.0, 0.0),
        }
    }

    fn time_step(fps: f64) -> f64 {
        1.0 / fps
    }

    fn apply(_: &GliderAircraft, c: GliderControls, action: GliderAction) -> GliderControls {
        let mut c = c;
        match action {
            GliderAction::PitchUp => c.lift_coefficient = (c.lift_coefficient + 0.05).min(1.4),
            GliderAction::PitchDown => c.lift_coefficient = (c.lift_coefficient - 0.05).max(0.0),
            GliderAction::BankLeft => c.bank_deg = (c.bank_deg - 5.0).max(-45.0),
            GliderAction::BankRight => c.bank_deg = (c.bank_deg + 5.0).min(45.0),
        }
        c
    }

    fn step(a: &GliderAircraft, c: &GliderControls, s: &GliderState, dt: f64) -> GliderState {
        let terms = GliderTerms::new(a, c);
        let (position_m, velocity_mps) =
            glider_step::<f64>(a, &terms, s.position_m.into(), s.velocity_mps.into(), dt);
        GliderState {
            time_s: s.time_s + dt,
            position_m: position_m.into(),
            velocity_mps: velocity_mps.into(),
        }
    }

    fn try_step(
        a: &GliderAircraft,
        c: &GliderControls,
        s: &GliderState,
        dt: f64,
    ) -> Result<GliderState, GliderError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(GliderError::InvalidTimeStep);
        }
        if !Self::is_finite(s) {
            return Err(GliderError::NonFinite);
        }
        let next = Self::step(a, c, s, dt);
        if Self::is_finite(&next) {
            Ok(next)
        } else {
            Err(GliderError::NonFinite)
        }
    }

    fn is_finite(s: &GliderState) -> bool {
        s.time_s.is_finite()
            && s.position_m.iter().all(|x| x.is_finite())
            && s.velocity_mps.iter().all(|x| x.is_finite())
    }

    fn height_m(s: &GliderState) -> f64 {
        s.position_m.z
    }

    fn climb_rate_mps(s: &GliderState) -> f64 {
        s.velocity_mps.z
    }

    fn view(_: &GliderAircraft, c: &GliderControls, s: &GliderState) -> FlightView {
        let v = s.velocity_mps;
        let speed = v.norm();
        let horizontal = v.x.hypot(v.y);
        // Heading clockwise from north: east is -y.
        let heading_deg = (-v.y).atan2(v.x).to_degrees().rem_euclid(360.0);
        FlightView {
            time_s: s.time_s,
            position_m: s.position_m,
            velocity_mps: v,
            attitude: Attitude {
                roll_deg: c.bank_deg,
                pitch_deg: v.z.atan2(horizontal).to_degrees(),
                heading_deg,
            },
            velocity_body_mps: Vector3::new(speed, 0.0, 0.0),
            airspeed_mps: speed,
            alpha_deg: 0.0,
            beta_deg: 0.0,
            flaps_norm: 0.0,
            engine_running: false,
            engine_rpm: 0.0,
            stalling: c.lift_coefficient >= 1.4,
        }
    }
}

/// What the glider's step reads of its controls: one aircraft's (`R = f64`)
/// or every lane's, computed when the controls are set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GliderTerms<R> {
    /// `cos` of the bank.
    pub cos_bank: R,
    /// `sin` of the bank.
    pub sin_bank: R,
    /// The lift coefficient.
    pub cl: R,
    /// The drag coefficient of the polar, `cd0 + k·CL²`.
    pub cd: R,
}

impl GliderTerms<f64> {
    /// The terms of `c` on `a`.
    #[must_use]
    pub fn new(a: &GliderAircraft, c: &GliderControls) -> Self {
        let bank = c.bank_deg.to_radians();
        let cl = c.lift_coefficient;
        Self {
            cos_bank: fdm_core::math::cos(bank),
            sin_bank: fdm_core::math::sin(bank),
            cl,
            cd: a.cd0 + a.induced_k * cl * cl,
        }
    }
}

/// The glider's one step, over any number type `R` (a float for one
/// aircraft, lanes for a fleet): position and velocity after `dt` seconds.
/// It calls no transcendental function (`sqrt` only), so it takes no
/// `fdm_core::real::Maths`: `exact` and `fast` are the same step.
///
/// | value | read | written |
/// |---|---|---|
/// | `velocity` | speed, direction, lift and drag | `v + (L + D + W) / m · dt` |
/// | `position` | | `p + v' · dt` (the new velocity) |
/// | [`GliderTerms`] | bank, CL, CD | never |
#[inline(always)]
pub fn glider_step<R: Real<Scalar = f64>>(
    a: &GliderAircraft,
    k: &GliderTerms<R>,
    position_m: V3<R>,
    velocity_mps: V3<R>,
    dt: f64,
) -> (V3<R>, V3<R>) {
    let c = R::splat;
    let v = velocity_mps;
    let speed = v.magnitude();
    let along = v / speed;
    // Lift acts perpendicular to the velocity, in the vertical plane
    // through it, tilted by the bank (right bank turns toward -y, east).
    let horizontal = V3::new(along.y, -along.x, c(0.0));
    let horizontal_right = horizontal / horizontal.magnitude();
    let up = horizontal_right.cross(along);
    let lift_direction = up * k.cos_bank + horizontal_right * k.sin_bank;
    let q_area = c(0.5 * a.air_density_kgpm3) * speed * speed * a.wing_area_m2;
    let lift = lift_direction * (q_area * k.cl);
    let drag = -along * (q_area * k.cd);
    let weight = V3::new(c(0.0), c(0.0), c(-a.mass_kg * G_MPS2));
    let velocity = v + (lift + drag + weight) / c(a.mass_kg) * c(dt);
    (position_m + velocity * c(dt), velocity)
}

/// Aircraft per block of a glider fleet.
const GLIDER_LANES: usize = 8;
type GliderLanes = F64s<GLIDER_LANES>;

/// The glider's lanes: what a `fdm_fleet::Fleet<Glider>` needs besides the
/// step (which is [`glider_step`] itself): moving one aircraft in and out of
/// a block of lanes.
impl LaneModel for Glider {
    type Lanes = GliderLanes;
    type Shared = ();
    /// Position and velocity.
    type Vars = [V3<GliderLanes>; 2];
    type Terms = GliderTerms<GliderLanes>;
    type AircraftError = std::convert::Infallible;
    const HAS_FAST: bool = false;
    const SUSPECT: f64 = 1e150;

    fn check_aircraft(_: &GliderAircraft) -> Result<(), Self::AircraftError> {
        Ok(())
    }

    fn shared(_: &GliderAircraft) {}

    fn idle(a: &GliderAircraft) -> (Self::Vars, Self::Terms) {
        let s = Self::initial_state();
        let t = GliderTerms::new(a, &Self::initial_controls());
        let splat = |v: Vector3<f64>| V3::splat(v.x, v.y, v.z);
        let terms = GliderTerms {
            cos_bank: F64s::splat(t.cos_bank),
            sin_bank: F64s::splat(t.sin_bank),
            cl: F64s::splat(t.cl),
            cd: F64s::splat(t.cd),
        };
        ([splat(s.position_m), splat(s.velocity_mps)], terms)
    }

    fn state(vars: &Self::Vars, time_s: f64, lane: usize) -> GliderState {
        GliderState {
            time_s,
            position_m: vars[0].lane(lane).into(),
            velocity_mps: vars[1].lane(lane).into(),
        }
    }

    fn set_state(vars: &mut Self::Vars, lane: usize, s: &GliderState) -> f64 {
        vars[0].set_lane(lane, s.position_m.into());
        vars[1].set_lane(lane, s.velocity_mps.into());
        s.time_s
    }

    fn set_controls(
        terms: &mut Self::Terms,
        lane: usize,
        a: &GliderAircraft,
        (): &(),
        c: &GliderControls,
    ) {
        let t = GliderTerms::new(a, c);
        terms.cos_bank.set_lane(lane, t.cos_bank);
        terms.sin_bank.set_lane(lane, t.sin_bank);
        terms.cl.set_lane(lane, t.cl);
        terms.cd.set_lane(lane, t.cd);
    }

    #[inline(always)]
    fn step_lanes<F: Maths>(
        a: &GliderAircraft,
        (): &(),
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: f64,
    ) -> Self::Vars {
        let (position, velocity) = glider_step::<GliderLanes>(a, terms, vars[0], vars[1], dt);
        [position, velocity]
    }

    fn for_each_component(vars: &Self::Vars, mut f: impl FnMut(GliderLanes)) {
        for v in vars {
            f(v.x);
            f(v.y);
            f(v.z);
        }
    }

    fn above_ground(vars: &Self::Vars) -> LaneMask<GLIDER_LANES> {
        vars[0].z.gt(0.0)
    }

    fn position_m(state: &GliderState) -> Vector3<f64> {
        state.position_m
    }
}
