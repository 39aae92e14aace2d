//! Bourg's loads and step written once over the number type [`BourgReal`]:
//! `f32` for one aircraft ([`super::step`], [`super::loads`]) and lane vectors
//! ([`F32s`](crate::real::F32s)) for a fleet ([`super::lanes`]).
//!
//! The operations and their order are those of the original C++ (see
//! [`super::ops`] and [`super::loads`]); the scalar `if`s are masks and
//! [`Real::select`]s (for `f32` plain `if`s):
//!
//! * the drag direction carried across elements whose local speed is not
//!   above 1 ft/s;
//! * `Normalize`'s tolerance (`m <= 1e-15` divides by 1) and flush (`|c| <
//!   1e-15` becomes `+0`);
//! * the clamp of the angle of attack's sine to ±1 (the original's two `if`s);
//! * the stall flag (a wing element's lift coefficient exactly 0);
//! * the pitch trim's blend of the elevators' coefficients;
//! * the quaternion renormalisation (skipped for a zero norm).
//!
//! The airfoil and rudder table look-ups are hooks of the number type
//! ([`BourgReal::airfoil`], [`BourgReal::rudder`]): the scalar search and
//! interpolation of [`super::airfoil`] for `f32`, branchless comparisons and
//! selects among the tables' constants (or, with the instruction set's lane
//! [`Permutes`], permutes of them) with the same interpolation for lanes (the
//! same bits: the unit tests of [`super::lanes`] compare them).
//!
//! What the step reads and writes:
//!
//! | value | read | written |
//! |---|---|---|
//! | `position` | by the Euler step | `position + velocity' * dt` |
//! | `velocity` | by the Euler step | `velocity + force / mass * dt` |
//! | `velocity_body` | by the loads (as of the previous step) | `QVRotate(~orientation', velocity')` |
//! | `angular_velocity` | by the loads and the step | `ω + I⁻¹ (M − ω × Iω) * dt` |
//! | `orientation` | by the loads (force to earth) and the step | `q + q ω' (0.5 dt)`, renormalised |
//! | `stalling` | never | by the loads |
//! | [`BourgTerms`] | thrust, rudder normal, tables, trim | never |

use nalgebra::{Matrix3, Quaternion};

use super::airfoil::{airfoil_coefficients, rudder_coefficients, G_FTPS2, RHO_SLUG_FT3};
use super::airframe::{BourgAircraft, Flap};
use super::controls::BourgControls;
use super::ops::{PI, TOL};
use crate::real::{Mask, Maths, Permutes, Real, V3};

/// `eight!(|i| expr)`: `[expr with i = 0, ..., expr with i = 7]`, evaluated
/// in that order: an array of the eight elements' values, each written once
/// (no zeroed array to fill). A macro, not a function taking a closure: the
/// compiler kept such closures out of line, compiled for the baseline
/// instruction set, in the fleet kernels (2.8 times slower).
macro_rules! eight {
    (|$i:ident| $e:expr) => {
        [
            {
                let $i: usize = 0;
                $e
            },
            {
                let $i: usize = 1;
                $e
            },
            {
                let $i: usize = 2;
                $e
            },
            {
                let $i: usize = 3;
                $e
            },
            {
                let $i: usize = 4;
                $e
            },
            {
                let $i: usize = 5;
                $e
            },
            {
                let $i: usize = 6;
                $e
            },
            {
                let $i: usize = 7;
                $e
            },
        ]
    };
}

/// The number type of Bourg's step: a [`Real`] over `f32` with the model's
/// table look-ups as hooks.
pub trait BourgReal: Real<Scalar = f32> {
    /// Which airfoil table each lane reads (a [`Flap`] for `f32`, one per
    /// lane for lane vectors).
    type Table: Copy + core::fmt::Debug + Send + Sync + 'static;
    /// Every lane reading `flap`'s tables.
    fn table(flap: Flap) -> Self::Table;
    /// Sets lane `i`'s table to `flap`'s.
    fn set_table_lane(table: &mut Self::Table, i: usize, flap: Flap);
    /// [`airfoil_coefficients`] of every lane's angle in its table; lanes
    /// may fetch the table's entries with `permutes` (the same bits).
    fn airfoil<P: Permutes>(angle_deg: Self, table: Self::Table, permutes: P) -> (Self, Self);
    /// [`rudder_coefficients`] of every lane's angle; lanes may fetch the
    /// table's entries with `permutes` (the same bits).
    fn rudder<P: Permutes>(angle_deg: Self, permutes: P) -> (Self, Self);
}

impl BourgReal for f32 {
    type Table = Flap;
    #[inline(always)]
    fn table(flap: Flap) -> Flap {
        flap
    }
    #[inline(always)]
    fn set_table_lane(table: &mut Flap, _: usize, flap: Flap) {
        *table = flap;
    }
    #[inline(always)]
    fn airfoil<P: Permutes>(angle_deg: f32, table: Flap, _: P) -> (f32, f32) {
        airfoil_coefficients(angle_deg, table)
    }
    #[inline(always)]
    fn rudder<P: Permutes>(angle_deg: f32, _: P) -> (f32, f32) {
        rudder_coefficients(angle_deg)
    }
}

/// A quaternion of [`Real`]s (`w` the scalar part), with the original's
/// operations in its order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Q4<R> {
    /// Scalar part.
    pub w: R,
    /// Vector part, x.
    pub x: R,
    /// Vector part, y.
    pub y: R,
    /// Vector part, z.
    pub z: R,
}

impl<R: Real> Q4<R> {
    /// `~q = (n, −v)`.
    #[inline(always)]
    #[must_use]
    pub fn conjugate(self) -> Self {
        Self {
            w: self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }

    /// Quaternion product `self * b`, each component summed left to right.
    #[inline(always)]
    #[must_use]
    pub fn product(self, b: Self) -> Self {
        let (n1, x1, y1, z1) = (self.w, self.x, self.y, self.z);
        let (n2, x2, y2, z2) = (b.w, b.x, b.y, b.z);
        Self {
            w: n1 * n2 - x1 * x2 - y1 * y2 - z1 * z2,
            x: n1 * x2 + x1 * n2 + y1 * z2 - z1 * y2,
            y: n1 * y2 + y1 * n2 + z1 * x2 - x1 * z2,
            z: n1 * z2 + z1 * n2 + x1 * y2 - y1 * x2,
        }
    }

    /// `self` times the pure quaternion `v`.
    #[inline(always)]
    #[must_use]
    pub fn mul_vec(self, v: V3<R>) -> Self {
        let (n, x, y, z) = (self.w, self.x, self.y, self.z);
        Self {
            w: -(x * v.x + y * v.y + z * v.z),
            x: n * v.x + y * v.z - z * v.y,
            y: n * v.y + z * v.x - x * v.z,
            z: n * v.z + x * v.y - y * v.x,
        }
    }

    /// `QVRotate`: the vector part of `(q * v) * ~q`.
    #[inline(always)]
    pub fn rotate(self, v: V3<R>) -> V3<R> {
        let t = self.mul_vec(v).product(self.conjugate());
        V3::new(t.x, t.y, t.z)
    }

    /// `sqrt(n² + x² + y² + z²)`, summed left to right.
    #[inline(always)]
    pub fn magnitude(self) -> R {
        (self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    /// Lane-wise `if mask { a } else { b }`.
    #[inline(always)]
    pub fn select(mask: R::Mask, a: Self, b: Self) -> Self {
        Self {
            w: R::select(mask, a.w, b.w),
            x: R::select(mask, a.x, b.x),
            y: R::select(mask, a.y, b.y),
            z: R::select(mask, a.z, b.z),
        }
    }
}

impl<R: Real> core::ops::Add for Q4<R> {
    type Output = Self;
    /// Component-wise sum.
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        Self {
            w: self.w + b.w,
            x: self.x + b.x,
            y: self.y + b.y,
            z: self.z + b.z,
        }
    }
}

impl<R: Real> core::ops::Mul<R> for Q4<R> {
    type Output = Self;
    /// Each component times `s`.
    #[inline(always)]
    fn mul(self, s: R) -> Self {
        Self {
            w: self.w * s,
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl<R: Real> core::ops::Div<R> for Q4<R> {
    type Output = Self;
    /// Each component divided by `s` (a true division per component).
    #[inline(always)]
    fn div(self, s: R) -> Self {
        Self {
            w: self.w / s,
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }
}

impl From<Quaternion<f32>> for Q4<f32> {
    #[inline(always)]
    fn from(q: Quaternion<f32>) -> Self {
        Self {
            w: q.coords.w,
            x: q.coords.x,
            y: q.coords.y,
            z: q.coords.z,
        }
    }
}

impl From<Q4<f32>> for Quaternion<f32> {
    #[inline(always)]
    fn from(q: Q4<f32>) -> Self {
        Self::new(q.w, q.x, q.y, q.z)
    }
}

impl V3<f32> {
    /// `Normalize`: divided by the magnitude `m` (by 1 if `m <= 1e-15`),
    /// components below 1e-15 in magnitude flushed to `+0`.
    #[inline(always)]
    #[must_use]
    pub fn normalize_f32(self) -> Self {
        normalize(self)
    }
}

/// `Normalize` over any [`BourgReal`] (see [`super::ops::normalize`]).
#[inline(always)]
pub(crate) fn normalize<R: Real<Scalar = f32>>(u: V3<R>) -> V3<R> {
    let m = u.magnitude();
    let m = R::select(m.le(TOL), R::splat(1.0), m);
    let flush = |c: R| R::select(c.abs().lt(TOL), R::splat(0.0), c);
    V3::new(flush(u.x / m), flush(u.y / m), flush(u.z / m))
}

/// Matrix times vector: row-wise dot products, each summed left to right.
#[inline(always)]
pub(crate) fn mat_mul_vec<R: Real<Scalar = f32>>(m: &Matrix3<f32>, u: V3<R>) -> V3<R> {
    let c = R::splat;
    V3::new(
        c(m.m11) * u.x + c(m.m12) * u.y + c(m.m13) * u.z,
        c(m.m21) * u.x + c(m.m22) * u.y + c(m.m23) * u.z,
        c(m.m31) * u.x + c(m.m32) * u.y + c(m.m33) * u.z,
    )
}

/// What Bourg's loads read of one aircraft's controls (and the aircraft), per
/// lane: computed with every step for one aircraft, when the controls are set
/// in a fleet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BourgTerms<R: BourgReal> {
    /// Thrust along body x, lb.
    pub thrust_lb: R,
    /// The rudder's (element 6's) normal at its current incidence.
    pub rudder_normal: V3<R>,
    /// The airfoil table of elements 0..=5
    /// ([`BourgControls::element_flap`]).
    pub tables: [R::Table; 6],
    /// Whether the elevators (elements 4 and 5) blend toward the pitch trim's
    /// tables ([`BourgControls::elevator_coefficients`]).
    pub trimmed: R::Mask,
    /// The pitch trim's tables.
    pub trim_tables: R::Table,
    /// The pitch trim's blend factor, `|pitch_trim|` clamped to 1.
    pub trim: R,
}

impl BourgTerms<f32> {
    /// The terms of `controls` on `aircraft`.
    #[inline(always)]
    #[must_use]
    pub fn new(aircraft: &BourgAircraft, controls: &BourgControls) -> Self {
        let c = controls;
        let elements = &aircraft.airframe().elements;
        // `elevator_coefficients`' trim (NaN included).
        let (trim_tables, trim) = c.trim_tables();
        Self {
            thrust_lb: c.thrust_lb,
            rudder_normal: aircraft
                .rudder_normal(c.rudder_incidence_deg(&elements[6]))
                .into(),
            tables: core::array::from_fn(|i| c.element_flap(i, &elements[i])),
            trimmed: c.elevators == Flap::Neutral && c.pitch_trim != 0.0,
            trim_tables,
            trim,
        }
    }
}

impl<R: BourgReal> BourgTerms<R> {
    /// Every lane `t`.
    #[must_use]
    pub fn splat(t: &BourgTerms<f32>) -> Self {
        Self {
            thrust_lb: R::splat(t.thrust_lb),
            rudder_normal: V3::splat(t.rudder_normal.x, t.rudder_normal.y, t.rudder_normal.z),
            tables: t.tables.map(R::table),
            trimmed: R::Mask::splat(t.trimmed),
            trim_tables: R::table(t.trim_tables),
            trim: R::splat(t.trim),
        }
    }

    /// Sets lane `i` to `t`.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, t: &BourgTerms<f32>) {
        self.thrust_lb.set_lane(i, t.thrust_lb);
        self.rudder_normal.set_lane(i, t.rudder_normal);
        for (table, &flap) in self.tables.iter_mut().zip(&t.tables) {
            R::set_table_lane(table, i, flap);
        }
        self.trimmed.set_lane(i, t.trimmed);
        R::set_table_lane(&mut self.trim_tables, i, t.trim_tables);
        self.trim.set_lane(i, t.trim);
    }
}

/// Bourg's integrated state (the clock aside) of one aircraft or of lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BourgVars<R: Real> {
    /// Position of the CG, earth frame, ft.
    pub position_ft: V3<R>,
    /// Velocity, earth frame, ft/s.
    pub velocity_ftps: V3<R>,
    /// Velocity in the body frame, ft/s, as of the end of the previous step.
    pub velocity_body_ftps: V3<R>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_radps: V3<R>,
    /// Attitude, body → earth.
    pub orientation: Q4<R>,
    /// Whether a wing element had zero lift coefficient in the last step.
    pub stalling: R::Mask,
}

/// The loads of every lane (the original's `CalcAirplaneLoads`, see
/// [`super::loads`]): earth-frame force, body-frame moment, stall flag.
#[inline(always)]
#[allow(clippy::similar_names)]
pub(crate) fn loads<R: BourgReal, F: Maths, P: Permutes>(
    permutes: P,
    aircraft: &BourgAircraft,
    terms: &BourgTerms<R>,
    s: &BourgVars<R>,
) -> (V3<R>, V3<R>, R::Mask) {
    let mass = aircraft.mass_properties();
    let elements = &aircraft.airframe().elements;
    let c = R::splat;
    let zero = V3::splat(0.0, 0.0, 0.0);
    let splat3 = |v: &nalgebra::Vector3<f32>| V3::splat(v.x, v.y, v.z);

    // The original is one loop over the elements. Each element's quantities
    // depend on the others only through the carried drag direction and the
    // running sums, so they are computed here phase by phase for all eight
    // elements: every value comes from the same expression on the same
    // inputs, but the eight dependency chains (sqrt, divisions, asin) are
    // independent and the CPU can overlap them. The sums stay in element
    // order.
    let normal = |i: usize| {
        if i == 6 {
            terms.rudder_normal
        } else {
            splat3(&mass.normals[i])
        }
    };
    let cg_offset = |i: usize| splat3(&mass.cg_offsets_ft[i]);

    // The per-element arrays are built by `eight!` (each element written
    // once) rather than zeroed and then filled, which the compiler did with
    // a `memset` of 1.5 kB per array for 16 lanes (about 5 % of the fleet
    // kernel's time; BENCHMARKS.md, "Bourg: the asinf filter, the loads'
    // arrays, several frames in cache").
    // `vDragVector` is declared once before the loop: an element whose local
    // speed is not above 1 ft/s keeps the previous element's drag direction
    // (zero before the first update).
    let (local_speed, drag) = if R::LANES == 1 {
        // For one aircraft, filled loops: the arrays are small, and the
        // scalar step was 25 to 30 % slower with `eight!` for these arrays
        // and the resultants (measured; the compiler vectorised the eight
        // elements' operations less).
        let mut local_speed = [c(0.0); 8];
        let mut drag_candidate = [zero; 8];
        for i in 0..8 {
            let local_velocity =
                s.velocity_body_ftps + s.angular_velocity_radps.cross(cg_offset(i));
            local_speed[i] = local_velocity.magnitude();
            drag_candidate[i] = -local_velocity / local_speed[i];
        }
        let mut drag = [zero; 8];
        let mut carried = zero;
        for i in 0..8 {
            carried = V3::select(local_speed[i].gt(1.0), drag_candidate[i], carried);
            drag[i] = carried;
        }
        (local_speed, drag)
    } else {
        let local_velocity =
            eight!(|i| s.velocity_body_ftps + s.angular_velocity_radps.cross(cg_offset(i)));
        let local_speed = eight!(|i| local_velocity[i].magnitude());
        let drag_candidate = eight!(|i| -local_velocity[i] / local_speed[i]);
        let mut carried = zero;
        let drag = eight!(|i| {
            carried = V3::select(local_speed[i].gt(1.0), drag_candidate[i], carried);
            carried
        });
        (local_speed, drag)
    };

    // Each element's lift direction and the sine of its angle of attack. For
    // one aircraft the eight sines and their `asinf`s come first and the
    // lift directions after: the same operations on the same values, but
    // the `asinf`s (the longest chain) start earlier, which made the scalar
    // step about 20 % faster on an Intel Xeon (BENCHMARKS.md, "Scalar
    // steps"). For lanes the two stay in one loop: the other order made
    // the fleet kernel 10 to 20 % slower there.
    let mut sin_attack = [c(0.0); 8];
    // `RadiansToDegrees(asinf(s))`, the eight `asinf`s together (for one
    // aircraft, as eight lanes: the same bits, `Real::asinf_exact_8`).
    // Element by element, not with `.map(..)`, which the compiler could keep
    // out of line in the fleet kernels (see `real::lanes`).
    let (lift, [a0, a1, a2, a3, a4, a5, a6, a7]) = if R::LANES == 1 {
        for (i, s) in sin_attack.iter_mut().enumerate() {
            *s = sine_of_attack(drag[i], normal(i));
        }
        let asin = F::asinf_8(sin_attack);
        let mut lift = [zero; 8];
        for (i, l) in lift.iter_mut().enumerate() {
            *l = lift_direction(drag[i], normal(i));
        }
        (lift, asin)
    } else {
        let lift = eight!(|i| {
            sin_attack[i] = sine_of_attack(drag[i], normal(i));
            lift_direction(drag[i], normal(i))
        });
        (lift, F::asinf_8(sin_attack))
    };
    let deg = |a: R| a * 180.0 / PI;
    let attack_deg = [
        deg(a0),
        deg(a1),
        deg(a2),
        deg(a3),
        deg(a4),
        deg(a5),
        deg(a6),
        deg(a7),
    ];

    let mut stalling = R::Mask::splat(false);
    // Element `i`'s resultant (and the stall flag of the wing's elements).
    macro_rules! resultant_of {
        ($i:expr) => {{
            let i: usize = $i;
            let q_area =
                c(0.5) * RHO_SLUG_FT3 * local_speed[i] * local_speed[i] * elements[i].area_ft2;
            let (a, l, d) = (attack_deg[i], lift[i], drag[i]);
            match i {
                6 => {
                    let (cl, cd) = R::rudder(a, permutes);
                    (l * cl + d * cd) * q_area
                }
                7 => d * c(0.5) * q_area,
                _ => {
                    let (cl, cd) = elevator_coefficients::<R, P>(permutes, terms, i, a);
                    if i <= 3 {
                        stalling = stalling.or(cl.eq(0.0));
                    }
                    (l * cl + d * cd) * q_area
                }
            }
        }};
    }
    // For one aircraft a filled loop, for lanes `eight!` (as above: the
    // zeroed array of lanes was a `memset`, and the lanes' kernel was 40 %
    // slower with this loop).
    let resultant = if R::LANES == 1 {
        let mut resultant = [zero; 8];
        for (i, r) in resultant.iter_mut().enumerate() {
            *r = resultant_of!(i);
        }
        resultant
    } else {
        eight!(|i| resultant_of!(i))
    };

    let thrust = V3::new(
        c(1.0) * terms.thrust_lb,
        c(0.0) * terms.thrust_lb,
        c(0.0) * terms.thrust_lb,
    );
    let mut fb = zero;
    let mut mb = zero;
    for (i, r) in resultant.iter().enumerate() {
        fb = fb + *r;
        mb = mb + cg_offset(i).cross(*r);
    }

    fb = fb + thrust;
    let mut force_earth = s.orientation.rotate(fb);
    force_earth.z = force_earth.z + G_FTPS2 * mass.mass_slug;
    (force_earth, zero + mb, stalling)
}

/// An element's lift direction: `Normalize((drag × normal) × drag)`.
#[inline(always)]
fn lift_direction<R: Real<Scalar = f32>>(drag: V3<R>, normal: V3<R>) -> V3<R> {
    normalize(drag.cross(normal).cross(drag))
}

/// The sine of an element's angle of attack, `drag · normal`, clamped to
/// ±1 (the original's two `if`s).
#[inline(always)]
fn sine_of_attack<R: Real<Scalar = f32>>(drag: V3<R>, normal: V3<R>) -> R {
    let c = R::splat;
    let s = drag.dot(normal);
    let s = R::select(s.gt(1.0), c(1.0), s);
    R::select(s.lt(-1.0), c(-1.0), s)
}

/// [`BourgControls::elevator_coefficients`] of element `i` in every lane:
/// the element's table, blended toward the pitch trim's for the elevators
/// (4 and 5) of the lanes whose trim is set.
#[inline(always)]
fn elevator_coefficients<R: BourgReal, P: Permutes>(
    permutes: P,
    terms: &BourgTerms<R>,
    i: usize,
    angle_deg: R,
) -> (R, R) {
    let base = R::airfoil(angle_deg, terms.tables[i], permutes);
    if (i == 4 || i == 5) && terms.trimmed.any() {
        let (cl, cd) = R::airfoil(angle_deg, terms.trim_tables, permutes);
        let t = terms.trim;
        (
            R::select(terms.trimmed, base.0 + (cl - base.0) * t, base.0),
            R::select(terms.trimmed, base.1 + (cd - base.1) * t, base.1),
        )
    } else {
        base
    }
}

/// The original's `StepSimulation` for every lane: [`loads`], then
/// semi-implicit Euler (see [`super::step`]), the clock aside; the look-ups
/// with `permutes`.
#[inline(always)]
pub(crate) fn step<R: BourgReal, F: Maths, P: Permutes>(
    permutes: P,
    aircraft: &BourgAircraft,
    terms: &BourgTerms<R>,
    s: &BourgVars<R>,
    dt: f32,
) -> BourgVars<R> {
    let mass = aircraft.mass_properties();
    let c = R::splat;
    let (force_earth, moment_body, stalling) = loads::<R, F, P>(permutes, aircraft, terms, s);

    let acceleration = force_earth / c(mass.mass_slug);
    let velocity = s.velocity_ftps + acceleration * c(dt);
    let position = s.position_ft + velocity * c(dt);

    let omega = s.angular_velocity_radps;
    let gyroscopic = omega.cross(mat_mul_vec(&mass.inertia, omega));
    let angular_velocity =
        omega + mat_mul_vec(&mass.inertia_inverse, moment_body - gyroscopic) * c(dt);

    let spin = s.orientation.mul_vec(angular_velocity) * c(0.5 * dt);
    let orientation = s.orientation + spin;
    let norm = orientation.magnitude();
    let orientation = Q4::select(norm.eq(0.0), orientation, orientation / norm);

    BourgVars {
        position_ft: position,
        velocity_ftps: velocity,
        velocity_body_ftps: orientation.conjugate().rotate(velocity),
        angular_velocity_radps: angular_velocity,
        orientation,
        stalling,
    }
}
