//! The state, the loads (`CalcAirplaneLoads`) and the Euler step
//! (`StepSimulation`).

use core::fmt;

use nalgebra::{Quaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::airframe::{AircraftOf, Flap};
use super::controls::BourgControlsOf;
use super::float::BourgFloat;
use super::ops::{
    conjugate, cross, dot, euler_deg_from_quat, magnitude, mat_mul_vec, normalize, quat_add,
    quat_div, quat_from_euler_deg, quat_magnitude, quat_mul_vec, quat_scale, qv_rotate,
    radians_to_degrees,
};

/// The aircraft's integrated state, in float type `F` (see [`BourgState`]).
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
#[serde(bound = "F: BourgFloat")]
pub struct BourgStateOf<F: BourgFloat> {
    /// Simulated time, s: the sum of the time steps taken (each widened from
    /// `F` to `f64` exactly). The original keeps no clock; nothing in the
    /// dynamics reads it.
    pub time_s: f64,
    /// Position of the CG, earth frame, ft.
    pub position_ft: Vector3<F>,
    /// Velocity, earth frame, ft/s.
    pub velocity_ftps: Vector3<F>,
    /// Velocity in the body frame, ft/s, as of the end of the previous step:
    /// the loads use it. It is zero in [`initial`](Self::initial) although the
    /// velocity is not, as in the original, so the first frame has no
    /// aerodynamic forces (only thrust and gravity).
    pub velocity_body_ftps: Vector3<F>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_radps: Vector3<F>,
    /// Attitude, body → earth, as a unit quaternion (`w` the scalar part).
    /// The step renormalises it every frame, as the original does.
    pub orientation: Quaternion<F>,
    /// Whether a wing element (0..=3) had zero lift coefficient in the last
    /// step (a by-product of the loads, kept so it need not be recomputed).
    pub stalling: bool,
}

/// The `f32` state (the original's type).
pub type BourgState = BourgStateOf<f32>;
/// The `f64` state.
pub type BourgState64 = BourgStateOf<f64>;

impl<F: BourgFloat> BourgStateOf<F> {
    /// The original's initial conditions: time 0, position (−5000, 0, 2000) ft,
    /// velocity (60, 0, 0) ft/s, no rotation, velocity_body 0, orientation
    /// from Euler angles (0, 0, 0) (the identity), not stalling.
    #[must_use]
    pub fn initial() -> Self {
        let zero = Vector3::new(F::ZERO, F::ZERO, F::ZERO);
        let f = F::from_f64;
        Self {
            time_s: 0.0,
            position_ft: Vector3::new(f(-5000.0), F::ZERO, f(2000.0)),
            velocity_ftps: Vector3::new(f(60.0), F::ZERO, F::ZERO),
            velocity_body_ftps: zero,
            angular_velocity_radps: zero,
            orientation: quat_from_euler_deg(&zero),
            stalling: false,
        }
    }

    /// Speed `|velocity|`, ft/s, as the original's `fSpeed` (the same `f32`
    /// operations; divide by 1.688 for the original's knots).
    #[must_use]
    pub fn speed_ftps(&self) -> F {
        magnitude(&self.velocity_ftps)
    }

    /// Euler angles from the orientation, degrees, as the original's
    /// `MakeEulerAnglesFromQ`: `x` roll, `y` pitch (positive nose-down), `z`
    /// yaw (positive left of north).
    #[must_use]
    pub fn euler_angles_deg(&self) -> Vector3<F> {
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
            if !(F::is_finite(v.x) && F::is_finite(v.y) && F::is_finite(v.z)) {
                return Some(name);
            }
        }
        let q = &self.orientation;
        if !(F::is_finite(q.coords.w)
            && F::is_finite(q.coords.x)
            && F::is_finite(q.coords.y)
            && F::is_finite(q.coords.z))
        {
            return Some("orientation");
        }
        None
    }
}

impl<F: BourgFloat> Default for BourgStateOf<F> {
    fn default() -> Self {
        Self::initial()
    }
}

/// Forces and moments of one frame (the output of [`loads`]), in float type
/// `F` (see [`Loads`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(bound = "F: BourgFloat")]
pub struct LoadsOf<F: BourgFloat> {
    /// Total force (aerodynamics, thrust and gravity), earth frame, lb.
    pub force_earth: Vector3<F>,
    /// Total moment about the CG, body frame, ft·lb.
    pub moment_body: Vector3<F>,
    /// Whether a wing element (0..=3) had zero lift coefficient (stall).
    pub stalling: bool,
}

/// The `f32` loads (the original's type).
pub type Loads = LoadsOf<f32>;
/// The `f64` loads.
pub type Loads64 = LoadsOf<f64>;

/// The airfoil tables' interval search, as the original: the first `i` with
/// `a[i] ≤ angle < a[i+1]`; `None` outside the table or for NaN.
#[inline(always)]
fn interval<F: BourgFloat, const N: usize>(a: &[F; N], angle: F) -> Option<usize> {
    (0..N - 1).find(|&i| a[i] <= angle && a[i + 1] > angle)
}

/// The original's linear interpolation in interval `i`:
/// `t[i] − (a[i] − angle)·(t[i] − t[i+1])/(a[i] − a[i+1])`.
#[inline(always)]
fn lerp<F: BourgFloat, const N: usize>(a: &[F; N], t: &[F; N], i: usize, angle: F) -> F {
    t[i] - (a[i] - angle) * (t[i] - t[i + 1]) / (a[i] - a[i + 1])
}

/// Lift and drag coefficients of a wing or elevator element at an angle of
/// attack in degrees, from the tables of `flap` (`LiftCoefficient`,
/// `DragCoefficient`; both use the same angle table, so the interval is
/// searched once). Outside −8..24° (or for NaN): CL 0, CD 0.75.
#[inline]
#[must_use]
pub fn airfoil_coefficients<F: BourgFloat>(angle_deg: F, flap: Flap) -> (F, F) {
    let (cl, cd) = match flap {
        Flap::Neutral => (&F::CL_NEUTRAL, &F::CD_NEUTRAL),
        Flap::TrailingEdgeDown => (&F::CL_TRAILING_EDGE_DOWN, &F::CD_TRAILING_EDGE_DOWN),
        Flap::TrailingEdgeUp => (&F::CL_TRAILING_EDGE_UP, &F::CD_TRAILING_EDGE_UP),
    };
    let a = &F::AIRFOIL_ALPHA_DEG;
    match interval(a, angle_deg) {
        Some(i) => (lerp(a, cl, i, angle_deg), lerp(a, cd, i, angle_deg)),
        None => (F::ZERO, F::CD_OUTSIDE),
    }
}

/// Lift coefficient of a wing or elevator element (`LiftCoefficient`); see
/// [`airfoil_coefficients`].
#[must_use]
pub fn lift_coefficient<F: BourgFloat>(angle_deg: F, flap: Flap) -> F {
    airfoil_coefficients(angle_deg, flap).0
}

/// Drag coefficient of a wing or elevator element (`DragCoefficient`); see
/// [`airfoil_coefficients`].
#[must_use]
pub fn drag_coefficient<F: BourgFloat>(angle_deg: F, flap: Flap) -> F {
    airfoil_coefficients(angle_deg, flap).1
}

/// Rudder lift and drag coefficients (`RudderLiftCoefficient`,
/// `RudderDragCoefficient`), symmetric: the tables at `|angle|`, the lift
/// negated for `angle < 0`. So CL jumps from +0.16 at 0° to −0.16 just below.
/// Outside ±24° (or for NaN): CL 0, CD 0.75.
#[inline]
#[must_use]
pub fn rudder_coefficients<F: BourgFloat>(angle_deg: F) -> (F, F) {
    let a = &F::RUDDER_ALPHA_DEG;
    let abs = F::abs(angle_deg);
    match interval(a, abs) {
        Some(i) => {
            let cl = lerp(a, &F::RUDDER_CL, i, abs);
            let cl = if angle_deg < F::ZERO { -cl } else { cl };
            (cl, lerp(a, &F::RUDDER_CD, i, abs))
        }
        None => (F::ZERO, F::CD_OUTSIDE),
    }
}

/// Rudder lift coefficient; see [`rudder_coefficients`].
#[must_use]
pub fn rudder_lift_coefficient<F: BourgFloat>(angle_deg: F) -> F {
    rudder_coefficients(angle_deg).0
}

/// Rudder drag coefficient; see [`rudder_coefficients`].
#[must_use]
pub fn rudder_drag_coefficient<F: BourgFloat>(angle_deg: F) -> F {
    rudder_coefficients(angle_deg).1
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
/// [`AircraftOf::rudder_normal`]; `drag·0.5·q` for the fuselage, element 7);
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
pub fn loads<F: BourgFloat>(
    aircraft: &AircraftOf<F>,
    controls: &BourgControlsOf<F>,
    state: &BourgStateOf<F>,
) -> LoadsOf<F> {
    let mass = aircraft.mass_properties();
    let elements = &aircraft.airframe().elements;
    let zero = Vector3::new(F::ZERO, F::ZERO, F::ZERO);

    // The original is one loop over the elements. Each element's quantities
    // depend on the others only through the carried drag direction and the
    // running sums, so they are computed here phase by phase for all eight
    // elements: every value comes from the same expression on the same inputs
    // (bit-identical), but the eight dependency chains (sqrt, divisions, asin)
    // are independent and the CPU can overlap them. The sums stay in element
    // order.
    let mut normals = mass.normals;
    normals[6] = aircraft.rudder_normal(controls.rudder_incidence_deg(&elements[6]));

    let mut local_speed = [F::ZERO; 8];
    let mut drag_candidate = [zero; 8];
    for i in 0..8 {
        let local_velocity =
            state.velocity_body_ftps + cross(&state.angular_velocity_radps, &mass.cg_offsets_ft[i]);
        local_speed[i] = magnitude(&local_velocity);
        drag_candidate[i] = -local_velocity / local_speed[i];
    }

    // `vDragVector` is declared once before the loop: an element whose local
    // speed is not above 1 ft/s keeps the previous element's drag direction
    // (zero before the first update).
    let mut drag = [zero; 8];
    let mut carried = zero;
    for i in 0..8 {
        if local_speed[i] > F::ONE {
            carried = drag_candidate[i];
        }
        drag[i] = carried;
    }

    let mut lift = [zero; 8];
    let mut sin_attack = [F::ZERO; 8];
    for i in 0..8 {
        lift[i] = normalize(&cross(&cross(&drag[i], &normals[i]), &drag[i]));
        let mut s = dot(&drag[i], &normals[i]);
        if s > F::ONE {
            s = F::ONE;
        }
        if s < -F::ONE {
            s = -F::ONE;
        }
        sin_attack[i] = s;
    }

    let attack_deg = sin_attack.map(|s| radians_to_degrees(F::asin(s)));

    let mut stalling = false;
    let mut resultant = [zero; 8];
    for (i, element) in elements.iter().enumerate() {
        let q_area = F::HALF * F::RHO_SLUG_FT3 * local_speed[i] * local_speed[i] * element.area_ft2;
        let (a, l, d) = (attack_deg[i], &lift[i], &drag[i]);
        resultant[i] = match i {
            6 => {
                let (cl, cd) = rudder_coefficients(a);
                (l * cl + d * cd) * q_area
            }
            7 => d * F::HALF * q_area,
            _ => {
                let (cl, cd) = controls.elevator_coefficients(i, element, a);
                if i <= 3 && cl == F::ZERO {
                    stalling = true;
                }
                (l * cl + d * cd) * q_area
            }
        };
    }

    let thrust = Vector3::new(F::ONE, F::ZERO, F::ZERO) * controls.thrust_lb;
    let mut fb = zero;
    let mut mb = zero;
    for (r, cg_offset) in resultant.iter().zip(&mass.cg_offsets_ft) {
        fb += r;
        mb += cross(cg_offset, r);
    }

    fb += thrust;
    let mut force_earth = qv_rotate(&state.orientation, &fb);
    force_earth.z += F::G_FTPS2 * mass.mass_slug;

    LoadsOf {
        force_earth,
        moment_body: zero + mb,
        stalling,
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
/// outputs nothing reads back, so [`BourgStateOf::speed_ftps`] and
/// [`BourgStateOf::euler_angles_deg`] compute them (identically) on demand.
///
/// `aircraft` is the airframe with its mass properties (computed once),
/// `controls` this frame's settings (after [`BourgControlsOf::neutralize_surfaces`]
/// and the frame's [`BourgControlsOf::apply`] calls), `state` the state after
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
pub fn step<F: BourgFloat>(
    aircraft: &AircraftOf<F>,
    controls: &BourgControlsOf<F>,
    state: &BourgStateOf<F>,
    dt: F,
) -> BourgStateOf<F> {
    let mass = aircraft.mass_properties();
    let loads = loads(aircraft, controls, state);

    let acceleration = loads.force_earth / mass.mass_slug;
    let velocity = state.velocity_ftps + acceleration * dt;
    let position = state.position_ft + velocity * dt;

    let omega = state.angular_velocity_radps;
    let gyroscopic = cross(&omega, &mat_mul_vec(&mass.inertia, &omega));
    let angular_velocity =
        omega + mat_mul_vec(&mass.inertia_inverse, &(loads.moment_body - gyroscopic)) * dt;

    let spin = quat_scale(
        &quat_mul_vec(&state.orientation, &angular_velocity),
        F::HALF * dt,
    );
    let mut orientation = quat_add(&state.orientation, &spin);
    let norm = quat_magnitude(&orientation);
    if norm != F::ZERO {
        orientation = quat_div(&orientation, norm);
    }

    BourgStateOf {
        time_s: state.time_s + dt.to_f64(),
        position_ft: position,
        velocity_ftps: velocity,
        velocity_body_ftps: qv_rotate(&conjugate(&orientation), &velocity),
        angular_velocity_radps: angular_velocity,
        orientation,
        stalling: loads.stalling,
    }
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
pub fn try_step<F: BourgFloat>(
    aircraft: &AircraftOf<F>,
    controls: &BourgControlsOf<F>,
    state: &BourgStateOf<F>,
    dt: F,
) -> Result<BourgStateOf<F>, StepError> {
    if let Some(field) = state.first_non_finite() {
        return Err(StepError::NonFiniteState { field });
    }
    if !(F::is_finite(controls.thrust_lb)
        && F::is_finite(controls.rudder_deg)
        && F::is_finite(controls.pitch_trim))
    {
        return Err(StepError::NonFiniteControls);
    }
    if !(F::is_finite(dt) && dt > F::ZERO) {
        return Err(StepError::InvalidTimeStep);
    }
    let next = step(aircraft, controls, state, dt);
    match next.first_non_finite() {
        Some(field) => Err(StepError::NonFiniteResult { field }),
        None => Ok(next),
    }
}
