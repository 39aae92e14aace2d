//! The state, the loads (`CalcAirplaneLoads`) and the Euler step
//! (`StepSimulation`).

use core::fmt;

use nalgebra::{Quaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::airframe::BourgAircraft;
use super::controls::BourgControls;
use super::generic::{self, BourgTerms, BourgVars};
use super::ops::{euler_deg_from_quat, magnitude, quat_from_euler_deg};
use crate::real::{Exact, NoPermutes};

/// The aircraft's integrated state.
///
/// Earth frame: x north, y west, z up. Body frame: x forward, y left, z up.
///
/// Only what the step integrates (plus its clock and the stall flag the loads
/// produce on the way) is stored; the outputs the dynamics never read are
/// computed when asked: [`speed_ftps`](Self::speed_ftps) and
/// [`euler_angles_deg`](Self::euler_angles_deg) (the original computes both
/// at the end of every step; the Euler conversion alone was 18 % of a fleet
/// step).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgState {
    /// Simulated time, s: the sum of the time steps taken (each widened from
    /// `f32` to `f64` exactly). The original keeps no clock; nothing in the
    /// dynamics reads it.
    pub time_s: f64,
    /// Position of the CG, earth frame, ft.
    pub position_ft: Vector3<f32>,
    /// Velocity, earth frame, ft/s.
    pub velocity_ftps: Vector3<f32>,
    /// Velocity in the body frame, ft/s, as of the end of the previous step:
    /// the loads use it. It is zero in [`initial`](Self::initial) although the
    /// velocity is not, as in the original, so the first frame has no
    /// aerodynamic forces (only thrust and gravity).
    pub velocity_body_ftps: Vector3<f32>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_radps: Vector3<f32>,
    /// Attitude, body → earth, as a unit quaternion (`w` the scalar part).
    /// The step renormalises it every frame, as the original does.
    pub orientation: Quaternion<f32>,
    /// Whether a wing element (0..=3) had zero lift coefficient in the last
    /// step (a by-product of the loads, kept so it need not be recomputed).
    pub stalling: bool,
}

impl BourgState {
    /// The original's initial conditions: time 0, position (−5000, 0, 2000) ft,
    /// velocity (60, 0, 0) ft/s, no rotation, velocity_body 0, orientation
    /// from Euler angles (0, 0, 0) (the identity), not stalling.
    #[must_use]
    pub fn initial() -> Self {
        let zero = Vector3::<f32>::new(0.0, 0.0, 0.0);
        Self {
            time_s: 0.0,
            position_ft: Vector3::new(-5000.0, 0.0, 2000.0),
            velocity_ftps: Vector3::new(60.0, 0.0, 0.0),
            velocity_body_ftps: zero,
            angular_velocity_radps: zero,
            orientation: quat_from_euler_deg(&zero),
            stalling: false,
        }
    }

    /// Speed `|velocity|`, ft/s, as the original's `fSpeed` (the same `f32`
    /// operations; divide by 1.688 for the original's knots).
    #[must_use]
    pub fn speed_ftps(&self) -> f32 {
        magnitude(&self.velocity_ftps)
    }

    /// Euler angles from the orientation, degrees, as the original's
    /// `MakeEulerAnglesFromQ`: `x` roll, `y` pitch (positive nose-down), `z`
    /// yaw (positive left of north).
    #[must_use]
    pub fn euler_angles_deg(&self) -> Vector3<f32> {
        euler_deg_from_quat(&self.orientation)
    }

    /// Whether every number of the state is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.first_non_finite().is_none()
    }

    fn first_non_finite(&self) -> Option<&'static str> {
        if !self.time_s.is_finite() {
            return Some("time_s");
        }
        let vectors = [
            ("position_ft", &self.position_ft),
            ("velocity_ftps", &self.velocity_ftps),
            ("velocity_body_ftps", &self.velocity_body_ftps),
            ("angular_velocity_radps", &self.angular_velocity_radps),
        ];
        for (name, v) in vectors {
            if !(f32::is_finite(v.x) && f32::is_finite(v.y) && f32::is_finite(v.z)) {
                return Some(name);
            }
        }
        let q = &self.orientation;
        if !(f32::is_finite(q.coords.w)
            && f32::is_finite(q.coords.x)
            && f32::is_finite(q.coords.y)
            && f32::is_finite(q.coords.z))
        {
            return Some("orientation");
        }
        None
    }
}

impl Default for BourgState {
    fn default() -> Self {
        Self::initial()
    }
}

/// Forces and moments of one frame (the output of [`loads`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Loads {
    /// Total force (aerodynamics, thrust and gravity), earth frame, lb.
    pub force_earth: Vector3<f32>,
    /// Total moment about the CG, body frame, ft·lb.
    pub moment_body: Vector3<f32>,
    /// Whether a wing element (0..=3) had zero lift coefficient (stall).
    pub stalling: bool,
}

/// The forces and moments of one frame (the original's `CalcAirplaneLoads`).
///
/// For each element `i` in order 0..7: the local air velocity
/// `velocity_body + angular_velocity ^ cg_offset[i]`, its speed; the drag
/// direction `−v/|v|` — **only updated when the local speed exceeds 1 ft/s,
/// otherwise the previous element's drag direction is kept** (one variable
/// carried across the loop, as in the original, starting at zero); the lift
/// direction `Normalize((drag ^ normal) ^ drag)`; the angle of attack
/// `deg(asin(clamp(drag·normal, −1, 1)))`; the dynamic pressure times area
/// `0.5·rho·V·V·area`; the element force from the airfoil tables (rudder tables
/// for element 6, whose normal is that of the current rudder incidence,
/// [`BourgAircraft::rudder_normal`]; `drag·0.5·q` for the fuselage, element 7);
/// running sums of the forces and of `cg_offset[i] ^ force`. Then thrust along
/// body x is added, the force is rotated to the earth frame and gravity
/// `−32.174·mass` is added to its z.
///
/// Every value is computed with the original's expression in its operation
/// order, and the sums run in element order, so the `f32` result is bit-identical
/// to the C++ (the implementation evaluates the independent per-element
/// quantities element-wise in phases, which changes no value).
///
/// Pure: no allocation, no panics. NaN or infinite inputs propagate to NaN
/// outputs (table lookups of a NaN angle give CL 0, CD 0.75).
#[must_use]
pub fn loads(aircraft: &BourgAircraft, controls: &BourgControls, state: &BourgState) -> Loads {
    let terms = BourgTerms::new(aircraft, controls);
    let (force_earth, moment_body, stalling) =
        generic::loads::<f32, Exact, NoPermutes>(NoPermutes, aircraft, &terms, &vars(state));
    Loads {
        force_earth: force_earth.into(),
        moment_body: moment_body.into(),
        stalling,
    }
}

/// The state's integrated values as the generic step reads them.
#[inline(always)]
pub(crate) fn vars(state: &BourgState) -> BourgVars<f32> {
    BourgVars {
        position_ft: state.position_ft.into(),
        velocity_ftps: state.velocity_ftps.into(),
        velocity_body_ftps: state.velocity_body_ftps.into(),
        angular_velocity_radps: state.angular_velocity_radps.into(),
        orientation: state.orientation.into(),
        stalling: state.stalling,
    }
}

/// The state of `vars` at time `time_s`.
#[inline(always)]
pub(crate) fn state_of(vars: &BourgVars<f32>, time_s: f64) -> BourgState {
    BourgState {
        time_s,
        position_ft: vars.position_ft.into(),
        velocity_ftps: vars.velocity_ftps.into(),
        velocity_body_ftps: vars.velocity_body_ftps.into(),
        angular_velocity_radps: vars.angular_velocity_radps.into(),
        orientation: vars.orientation.into(),
        stalling: vars.stalling,
    }
}

/// Advances the state by `dt` seconds (the original's `StepSimulation`):
/// [`loads`], then semi-implicit Euler in the original's order:
///
/// ```text
/// velocity += (force / mass) * dt
/// position += velocity * dt                       (the new velocity)
/// angular_velocity += I⁻¹ (moment − ω ^ (I ω)) * dt
/// orientation += (orientation * angular_velocity) * (0.5 * dt)   (the new ω)
/// orientation /= |orientation|                    (unless 0)
/// velocity_body = QVRotate(~orientation, velocity)
/// time_s += dt
/// ```
///
/// The original also computes the speed and the Euler angles here; they are
/// outputs nothing reads back, so [`BourgState::speed_ftps`] and
/// [`BourgState::euler_angles_deg`] compute them (identically) on demand.
///
/// `aircraft` is the airframe with its mass properties (computed once),
/// `controls` this frame's settings (after [`BourgControls::neutralize_surfaces`]
/// and the frame's [`BourgControls::apply`] calls), `state` the state after
/// the previous frame, `dt` the time step in seconds (the reference runs use
/// `1.0f32 / 30.0`).
///
/// The input state's `stalling` is not read (it is an output); everything
/// else but `time_s` is.
///
/// Pure: no allocation, no panics, `no_std`. NaN or infinite inputs do not
/// panic; they propagate: a non-finite value in a field the dynamics read (or
/// in the thrust or `dt`) gives a state with non-finite fields. Use
/// [`try_step`] to get a [`StepError`] instead.
///
/// ```
/// use fdm_core::bourg::{step, BourgAircraft, BourgAction, BourgControls, BourgState};
///
/// let aircraft = BourgAircraft::bourg_default();
/// let mut controls = BourgControls::initial();
/// let mut state = BourgState::initial();
/// let dt = 1.0f32 / 30.0;
/// for frame in 1..=30 {
///     controls = controls.neutralize_surfaces();
///     if frame <= 5 {
///         controls = controls.apply(BourgAction::ThrustUp);
///     }
///     state = step(&aircraft, &controls, &state, dt);
/// }
/// assert_eq!(controls.thrust_lb, 1000.0);
/// assert!(state.position_ft.x > -5000.0 && state.position_ft.z < 2000.0);
/// ```
#[must_use]
pub fn step(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    state: &BourgState,
    dt: f32,
) -> BourgState {
    let terms = BourgTerms::new(aircraft, controls);
    let vars = vars(state);
    // In the CPU's AVX2 instance when it has one: the eight elements'
    // `asinf`s in one vector register, the same numbers
    // (`crate::math::with_fma`).
    let next = crate::math::with_fma(
        #[inline(always)]
        move || generic::step::<f32, Exact, NoPermutes>(NoPermutes, aircraft, &terms, &vars, dt),
    );
    state_of(&next, state.time_s + f64::from(dt))
}

/// Why [`try_step`] refused to step or to return a result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepError {
    /// A number of the input state is NaN or infinite.
    NonFiniteState {
        /// The field, e.g. `"angular_velocity"`.
        field: &'static str,
    },
    /// A control value (thrust, rudder or pitch trim) is NaN or infinite.
    NonFiniteControls,
    /// `dt` is NaN, infinite, zero or negative.
    InvalidTimeStep,
    /// The inputs were finite but the step overflowed to a non-finite state
    /// (e.g. absurd velocities).
    NonFiniteResult {
        /// The first non-finite field of the result.
        field: &'static str,
    },
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFiniteState { field } => write!(f, "state `{field}` is not finite"),
            Self::NonFiniteControls => f.write_str("a control value is not finite"),
            Self::InvalidTimeStep => f.write_str("the time step is not a finite positive number"),
            Self::NonFiniteResult { field } => {
                write!(f, "the step produced a non-finite `{field}`")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for StepError {}

/// [`step`] with checks: refuses non-finite inputs or a non-positive `dt`, and
/// reports a non-finite result instead of returning it. On success the result
/// is bit-identical to [`step`]'s.
///
/// # Errors
/// [`StepError`] naming the problem.
pub fn try_step(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    state: &BourgState,
    dt: f32,
) -> Result<BourgState, StepError> {
    if let Some(field) = state.first_non_finite() {
        return Err(StepError::NonFiniteState { field });
    }
    if !(f32::is_finite(controls.thrust_lb)
        && f32::is_finite(controls.rudder_deg)
        && f32::is_finite(controls.pitch_trim))
    {
        return Err(StepError::NonFiniteControls);
    }
    if !(f32::is_finite(dt) && dt > 0.0) {
        return Err(StepError::InvalidTimeStep);
    }
    let next = step(aircraft, controls, state, dt);
    match next.first_non_finite() {
        Some(field) => Err(StepError::NonFiniteResult { field }),
        None => Ok(next),
    }
}
