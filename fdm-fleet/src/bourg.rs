//! A fleet of Bourg aircraft (one shared [`BourgAircraft`], each with its own
//! state and controls) stepped [`LANES`] aircraft per SIMD instruction in
//! `f32`, every aircraft bit-identical to [`fdm_core::bourg::step`].
//!
//! The layout is that of [`crate::palmer`]: blocks of [`LANES`] aircraft, every
//! field its own `[f32; LANES]` (the clock `[f64; LANES]`), the last block
//! padded with idle aircraft.
//!
//! # A twin of the scalar step
//!
//! The kernel evaluates every value of `fdm_core::bourg::loads` and `step`
//! with the same `f32` operations in the same order, lane-wise (each formula
//! below carries the grouping of `fdm_core`'s `bourg/ops.rs`): additions,
//! multiplications, divisions and square roots are correctly rounded in SIMD as
//! in scalar code and are never fused (see [`crate::palmer`]'s note on FMA).
//! The scalar `if`s are lane masks: the drag direction carried across elements
//! below 1 ft/s, the `normalize` tolerance and flush, the clamp of the angle of
//! attack's sine, the stall flag and the quaternion renormalisation. The
//! airfoil and rudder table look-ups ([`airfoil_coefficients`](fdm_core::bourg::airfoil_coefficients),
//! [`rudder_coefficients`](fdm_core::bourg::rudder_coefficients)) become a branchless interval count over `fdm_core`'s
//! own tables (the three flap settings' tables of a coefficient laid end to
//! end, so a lane's table is an offset and its two entries are a gather) and a
//! lane-wise interpolation with the same formula (unit tests compare them with
//! the scalar functions bit for bit). The pitch trim's blend of the elevators'
//! coefficients ([`BourgControls::elevator_coefficients`], an extension of the
//! original) is evaluated lane-wise too, only in blocks where a lane has one.
//! Only glibc's `asinf` goes lane by lane (through the same
//! `fdm_core::math::asinf` the scalar step calls): a lane-wise port of
//! glibc 2.36's `asinf` (`sysdeps/ieee754/flt-32/e_asinf.c`) would remove
//! that call, but its single-precision polynomial and coefficients are
//! distributed under the LGPL 2.1 or later, which this crate (MIT OR
//! Apache-2.0) cannot take in, so it is not ported.
//!
//! What depends only on the controls is computed when they are set, with the
//! scalar step's functions: the rudder's normal at its incidence, the table
//! (flap setting) of each element, and the pitch trim's tables and factor.
//!
//! This module is written against `fdm_core::bourg`'s public API of the time;
//! `tests/bourg_fleet.rs` checks it against the scalar step bit for bit on the
//! reference scenarios and on random fleets.

use fdm_core::bourg::airfoil::{
    AIRFOIL_ALPHA_DEG, CD_NEUTRAL, CD_OUTSIDE, CD_TRAILING_EDGE_DOWN, CD_TRAILING_EDGE_UP,
    CL_NEUTRAL, CL_TRAILING_EDGE_DOWN, CL_TRAILING_EDGE_UP, G_FTPS2, RHO_SLUG_FT3,
    RUDDER_ALPHA_DEG, RUDDER_CD, RUDDER_CL,
};
use fdm_core::bourg::ops::{PI, TOL};
use fdm_core::bourg::Bourg;
use fdm_core::bourg::{BourgAircraft, BourgControls, BourgState, Flap, Quaternion, Vector3};
use fdm_core::math::asinf;
use fdm_core::model::{FlightStatus, Model};
use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

use crate::lanes::{F32s, Mask};

/// Aircraft per block: 16 f32 lanes (one AVX-512 register, two AVX2 ones).
pub const LANES: usize = 16;

/// Blocks per rayon task in [`BourgFleet::par_step`].
const BLOCKS_PER_TASK: usize = 32;

type L = F32s<LANES>;
type M = Mask<LANES>;

/// A 3-vector of lanes.
#[derive(Clone, Copy)]
struct V3 {
    x: L,
    y: L,
    z: L,
}

/// A quaternion of lanes (`w` the scalar part).
#[derive(Clone, Copy)]
struct Q4 {
    w: L,
    x: L,
    y: L,
    z: L,
}

impl V3 {
    #[inline(always)]
    fn splat(v: &Vector3<f32>) -> Self {
        Self {
            x: L::splat(v.x),
            y: L::splat(v.y),
            z: L::splat(v.z),
        }
    }

    #[inline(always)]
    fn load(a: &[[f32; LANES]; 3]) -> Self {
        Self {
            x: F32s(a[0]),
            y: F32s(a[1]),
            z: F32s(a[2]),
        }
    }

    #[inline(always)]
    fn store(self, a: &mut [[f32; LANES]; 3]) {
        a[0] = self.x.0;
        a[1] = self.y.0;
        a[2] = self.z.0;
    }

    /// nalgebra's `u + v`.
    #[inline(always)]
    fn add(self, v: Self) -> Self {
        Self {
            x: self.x + v.x,
            y: self.y + v.y,
            z: self.z + v.z,
        }
    }

    /// nalgebra's `u - v`.
    #[inline(always)]
    fn sub(self, v: Self) -> Self {
        Self {
            x: self.x - v.x,
            y: self.y - v.y,
            z: self.z - v.z,
        }
    }

    /// nalgebra's `u * s`.
    #[inline(always)]
    fn scale(self, s: L) -> Self {
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// nalgebra's `u / s`.
    #[inline(always)]
    fn div(self, s: L) -> Self {
        Self {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }

    /// `ops::cross`.
    #[inline(always)]
    fn cross(self, v: Self) -> Self {
        let u = self;
        Self {
            x: u.y * v.z - u.z * v.y,
            y: -u.x * v.z + u.z * v.x,
            z: u.x * v.y - u.y * v.x,
        }
    }

    /// `ops::dot`.
    #[inline(always)]
    fn dot(self, v: Self) -> L {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// `ops::magnitude`.
    #[inline(always)]
    fn magnitude(self) -> L {
        (self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    /// `ops::normalize`: divided by the magnitude (1 if that is `<= TOL`),
    /// components below `TOL` in magnitude flushed to zero.
    #[inline(always)]
    fn normalize(self) -> Self {
        let tol = TOL;
        let m = self.magnitude();
        let m = m.le(tol).select(L::splat(1.0), m);
        let flush = |c: L| c.abs().lt(tol).select(L::splat(0.0), c);
        Self {
            x: flush(self.x / m),
            y: flush(self.y / m),
            z: flush(self.z / m),
        }
    }

    /// Lane-wise `if mask { a } else { b }`.
    #[inline(always)]
    fn select(mask: M, a: Self, b: Self) -> Self {
        Self {
            x: mask.select(a.x, b.x),
            y: mask.select(a.y, b.y),
            z: mask.select(a.z, b.z),
        }
    }
}

/// `ops::mat_mul_vec` with a shared matrix.
#[inline(always)]
fn mat_mul_vec(m: &fdm_core::bourg::Matrix3<f32>, u: V3) -> V3 {
    V3 {
        x: m.m11 * u.x + m.m12 * u.y + m.m13 * u.z,
        y: m.m21 * u.x + m.m22 * u.y + m.m23 * u.z,
        z: m.m31 * u.x + m.m32 * u.y + m.m33 * u.z,
    }
}

impl Q4 {
    #[inline(always)]
    fn load(a: &[[f32; LANES]; 4]) -> Self {
        Self {
            w: F32s(a[0]),
            x: F32s(a[1]),
            y: F32s(a[2]),
            z: F32s(a[3]),
        }
    }

    #[inline(always)]
    fn store(self, a: &mut [[f32; LANES]; 4]) {
        a[0] = self.w.0;
        a[1] = self.x.0;
        a[2] = self.y.0;
        a[3] = self.z.0;
    }

    /// `ops::conjugate`.
    #[inline(always)]
    fn conjugate(self) -> Self {
        Self {
            w: self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }

    /// `ops::quat_mul`.
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let (n1, x1, y1, z1) = (self.w, self.x, self.y, self.z);
        let (n2, x2, y2, z2) = (b.w, b.x, b.y, b.z);
        Self {
            w: n1 * n2 - x1 * x2 - y1 * y2 - z1 * z2,
            x: n1 * x2 + x1 * n2 + y1 * z2 - z1 * y2,
            y: n1 * y2 + y1 * n2 + z1 * x2 - x1 * z2,
            z: n1 * z2 + z1 * n2 + x1 * y2 - y1 * x2,
        }
    }

    /// `ops::quat_mul_vec`.
    #[inline(always)]
    fn mul_vec(self, v: V3) -> Self {
        let (n, x, y, z) = (self.w, self.x, self.y, self.z);
        Self {
            w: -(x * v.x + y * v.y + z * v.z),
            x: n * v.x + y * v.z - z * v.y,
            y: n * v.y + z * v.x - x * v.z,
            z: n * v.z + x * v.y - y * v.x,
        }
    }

    /// `ops::qv_rotate`.
    #[inline(always)]
    fn rotate(self, v: V3) -> V3 {
        let t = self.mul_vec(v).mul(self.conjugate());
        V3 {
            x: t.x,
            y: t.y,
            z: t.z,
        }
    }
}

/// [`LANES`] aircraft, field by field.
#[derive(Debug, Clone, Copy)]
struct Block {
    time: [f64; LANES],
    position: [[f32; LANES]; 3],
    velocity: [[f32; LANES]; 3],
    velocity_body: [[f32; LANES]; 3],
    angular_velocity: [[f32; LANES]; 3],
    /// `w, x, y, z`.
    orientation: [[f32; LANES]; 4],
    stalling: [bool; LANES],
    thrust: [f32; LANES],
    /// The rudder's normal at its current incidence.
    rudder_normal: [[f32; LANES]; 3],
    /// The airfoil tables of elements 0..=5 ([`table_offset`]).
    tables: [[u32; LANES]; 6],
    /// Whether the elevators (elements 4 and 5) blend toward the pitch trim's
    /// tables ([`BourgControls::elevator_coefficients`]).
    trimmed: [bool; LANES],
    /// The pitch trim's tables ([`table_offset`]).
    trim_tables: [u32; LANES],
    /// The pitch trim's blend factor, `|pitch_trim|` clamped to 1.
    trim: [f32; LANES],
    controls: [BourgControls; LANES],
    /// Each aircraft's flight status ([`BourgFleet::fly`]).
    status: [FlightStatus; LANES],
}

/// The fields of a block that a step changes, as they were before it.
#[derive(Clone, Copy)]
struct Saved {
    time: [f64; LANES],
    position: [[f32; LANES]; 3],
    velocity: [[f32; LANES]; 3],
    velocity_body: [[f32; LANES]; 3],
    angular_velocity: [[f32; LANES]; 3],
    orientation: [[f32; LANES]; 4],
    stalling: [bool; LANES],
}

/// Beyond this magnitude a component of a stepped state sends its aircraft
/// down the scalar path of [`BourgFleet::fly`] (which then checks
/// [`Model::is_finite`] exactly): small enough that the speed of a state
/// whose components are all below it cannot overflow `f32`
/// (`3 · 1e18² < f32::MAX`), so every lane not flagged is finite for the
/// model.
const SUSPECT_F32: f32 = 1e18;

impl Block {
    fn idle(aircraft: &BourgAircraft) -> Self {
        let mut block = Self {
            time: [0.0; LANES],
            position: [[0.0; LANES]; 3],
            velocity: [[0.0; LANES]; 3],
            velocity_body: [[0.0; LANES]; 3],
            angular_velocity: [[0.0; LANES]; 3],
            orientation: [[1.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]],
            stalling: [false; LANES],
            thrust: [0.0; LANES],
            rudder_normal: [[0.0; LANES]; 3],
            tables: [[0; LANES]; 6],
            trimmed: [false; LANES],
            trim_tables: [0; LANES],
            trim: [0.0; LANES],
            controls: [BourgControls::initial(); LANES],
            status: [FlightStatus::Airborne; LANES],
        };
        for lane in 0..LANES {
            block.set_state(lane, &BourgState::initial());
            block.set_controls(lane, aircraft, BourgControls::initial());
        }
        block
    }

    fn set_state(&mut self, lane: usize, s: &BourgState) {
        self.time[lane] = s.time_s;
        let put = |a: &mut [[f32; LANES]; 3], v: &Vector3<f32>| {
            a[0][lane] = v.x;
            a[1][lane] = v.y;
            a[2][lane] = v.z;
        };
        put(&mut self.position, &s.position_ft);
        put(&mut self.velocity, &s.velocity_ftps);
        put(&mut self.velocity_body, &s.velocity_body_ftps);
        put(&mut self.angular_velocity, &s.angular_velocity_radps);
        let q = &s.orientation.coords;
        self.orientation[0][lane] = q.w;
        self.orientation[1][lane] = q.x;
        self.orientation[2][lane] = q.y;
        self.orientation[3][lane] = q.z;
        self.stalling[lane] = s.stalling;
    }

    fn saved(&self) -> Saved {
        Saved {
            time: self.time,
            position: self.position,
            velocity: self.velocity,
            velocity_body: self.velocity_body,
            angular_velocity: self.angular_velocity,
            orientation: self.orientation,
            stalling: self.stalling,
        }
    }

    /// Lane `lane`'s state as it was in `saved`.
    fn saved_state(saved: &Saved, lane: usize) -> BourgState {
        let get = |a: &[[f32; LANES]; 3]| Vector3::new(a[0][lane], a[1][lane], a[2][lane]);
        let o = &saved.orientation;
        BourgState {
            time_s: saved.time[lane],
            position_ft: get(&saved.position),
            velocity_ftps: get(&saved.velocity),
            velocity_body_ftps: get(&saved.velocity_body),
            angular_velocity_radps: get(&saved.angular_velocity),
            orientation: Quaternion::new(o[0][lane], o[1][lane], o[2][lane], o[3][lane]),
            stalling: saved.stalling[lane],
        }
    }

    /// The lanes whose stepped state may not be finite for the model: a
    /// component at or beyond [`SUSPECT_F32`] in magnitude, NaN, or a
    /// non-finite clock.
    #[inline(always)]
    fn suspect(&self) -> [bool; LANES] {
        let mut ok: [bool; LANES] = core::array::from_fn(|l| self.time[l].is_finite());
        let fields = self
            .position
            .iter()
            .chain(&self.velocity)
            .chain(&self.velocity_body)
            .chain(&self.angular_velocity)
            .chain(&self.orientation);
        for field in fields {
            for (ok, x) in ok.iter_mut().zip(field) {
                *ok &= x.abs() < SUSPECT_F32;
            }
        }
        ok.map(|ok| !ok)
    }

    /// The flight-status half of [`BourgFleet::fly`] for a block the kernel
    /// has just stepped from `saved`: every lane ends as
    /// [`fdm_core::model::fly`] would have left it.
    #[inline(always)]
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x < y)` is true for NaN, as wanted
    fn settle(&mut self, saved: &Saved, aircraft: &BourgAircraft, dt: f32) {
        // Whether any lane needs more than the step (usually none): one
        // lane-wise OR of integer flags, which vectorises.
        let mut flags = [0_u32; LANES];
        for (f, (&t, &s)) in flags.iter_mut().zip(self.time.iter().zip(&self.status)) {
            *f = u32::from(!t.is_finite()) | u32::from(s != FlightStatus::Airborne);
        }
        for (f, &z) in flags.iter_mut().zip(&self.position[2]) {
            *f |= u32::from(!(z > 0.0));
        }
        let fields = self
            .position
            .iter()
            .chain(&self.velocity)
            .chain(&self.velocity_body)
            .chain(&self.angular_velocity)
            .chain(&self.orientation);
        for field in fields {
            for (f, x) in flags.iter_mut().zip(field) {
                *f |= u32::from(!(x.abs() < SUSPECT_F32));
            }
        }
        if flags.iter().fold(0, |any, &f| any | f) == 0 {
            return;
        }
        let suspect = self.suspect();
        let airborne: [bool; LANES] = core::array::from_fn(|l| {
            (self.status[l] == FlightStatus::Airborne) & (self.position[2][l] > 0.0) & !suspect[l]
        });
        self.settle_lanes(&airborne, &suspect, saved, aircraft, dt);
    }

    /// The scalar part of [`Self::settle`], for the lanes not `airborne`
    /// (rare: out of the hot loop).
    #[cold]
    #[inline(never)]
    fn settle_lanes(
        &mut self,
        airborne: &[bool; LANES],
        suspect: &[bool; LANES],
        saved: &Saved,
        aircraft: &BourgAircraft,
        dt: f32,
    ) {
        for lane in 0..LANES {
            let status = self.status[lane];
            if airborne[lane] {
                continue;
            }
            let (state, status) = crate::finish_lane::<Bourg>(
                aircraft,
                &self.controls[lane],
                status,
                suspect[lane],
                || Self::saved_state(saved, lane),
                || self.state(lane),
                dt,
            );
            self.set_state(lane, &state);
            self.status[lane] = status;
        }
    }

    fn state(&self, lane: usize) -> BourgState {
        let get = |a: &[[f32; LANES]; 3]| Vector3::new(a[0][lane], a[1][lane], a[2][lane]);
        let o = &self.orientation;
        BourgState {
            time_s: self.time[lane],
            position_ft: get(&self.position),
            velocity_ftps: get(&self.velocity),
            velocity_body_ftps: get(&self.velocity_body),
            angular_velocity_radps: get(&self.angular_velocity),
            orientation: Quaternion::new(o[0][lane], o[1][lane], o[2][lane], o[3][lane]),
            stalling: self.stalling[lane],
        }
    }

    fn set_controls(&mut self, lane: usize, aircraft: &BourgAircraft, c: BourgControls) {
        let elements = &aircraft.airframe().elements;
        let normal = aircraft.rudder_normal(c.rudder_incidence_deg(&elements[6]));
        self.rudder_normal[0][lane] = normal.x;
        self.rudder_normal[1][lane] = normal.y;
        self.rudder_normal[2][lane] = normal.z;
        for (i, tables) in self.tables.iter_mut().enumerate() {
            tables[lane] = table_offset(c.element_flap(i, &elements[i]));
        }
        // `elevator_coefficients`' trim, in its operations (NaN included).
        self.trimmed[lane] = c.elevators == Flap::Neutral && c.pitch_trim != 0.0;
        let (flap, mut t) = if c.pitch_trim > 0.0 {
            (Flap::TrailingEdgeUp, c.pitch_trim)
        } else {
            (Flap::TrailingEdgeDown, -c.pitch_trim)
        };
        if t > 1.0 {
            t = 1.0;
        }
        self.trim_tables[lane] = table_offset(flap);
        self.trim[lane] = t;
        self.thrust[lane] = c.thrust_lb;
        self.controls[lane] = c;
    }
}

/// Three tables of one coefficient one after the other, in the order of
/// [`table_offset`].
const fn concat(neutral: &[f32; 9], down: &[f32; 9], up: &[f32; 9]) -> [f32; 27] {
    let mut out = [0.0; 27];
    let mut i = 0;
    while i < 9 {
        out[i] = neutral[i];
        out[9 + i] = down[i];
        out[18 + i] = up[i];
        i += 1;
    }
    out
}

/// The airfoil lift tables, neutral, trailing edge down, trailing edge up.
const CL_TABLES: [f32; 27] = concat(&CL_NEUTRAL, &CL_TRAILING_EDGE_DOWN, &CL_TRAILING_EDGE_UP);
/// The airfoil drag tables, in the same order.
const CD_TABLES: [f32; 27] = concat(&CD_NEUTRAL, &CD_TRAILING_EDGE_DOWN, &CD_TRAILING_EDGE_UP);

/// Where `flap`'s table starts in [`CL_TABLES`] and [`CD_TABLES`].
const fn table_offset(flap: Flap) -> u32 {
    match flap {
        Flap::Neutral => 0,
        Flap::TrailingEdgeDown => 9,
        Flap::TrailingEdgeUp => 18,
    }
}

/// `table[i]`, `i` clamped to the table (a no-op for the indexes the
/// look-ups make; it lets the compiler drop the bounds check and gather).
#[inline(always)]
fn entry(table: &[f32], i: u32) -> f32 {
    table[(i as usize).min(table.len() - 1)]
}

/// The scalar look-up's interval search, lane-wise: in a strictly increasing
/// table `a`, the first `i` with `a[i] <= angle < a[i + 1]` is the number of
/// entries `<= angle` minus one, and it exists exactly when
/// `a[0] <= angle < a[last]` (false for NaN). Lanes without one get index 0
/// and a cleared mask.
#[inline(always)]
fn interval_lanes<const T: usize>(a: &[f32; T], angle: L) -> ([u32; LANES], M) {
    let mut count = [0_u32; LANES];
    for &entry in a {
        for (c, &x) in count.iter_mut().zip(&angle.0) {
            *c += u32::from(entry <= x);
        }
    }
    let valid = Mask(core::array::from_fn(|l| {
        a[0] <= angle.0[l] && angle.0[l] < a[T - 1]
    }));
    let index = core::array::from_fn(|l| {
        if valid.0[l] {
            count[l].wrapping_sub(1)
        } else {
            0
        }
    });
    (index, valid)
}

/// The scalar `lerp` in each lane's interval:
/// `t[i] - (a[i] - angle) * (t[i] - t[i+1]) / (a[i] - a[i+1])`, lane `l`'s
/// table `t` starting at `tables[offset[l]]`.
#[inline(always)]
fn lerp_lanes<const T: usize>(
    a: &[f32; T],
    tables: &[f32],
    offset: &[u32; LANES],
    index: &[u32; LANES],
    angle: L,
) -> L {
    let a0 = F32s(core::array::from_fn(|l| entry(a, index[l])));
    let a1 = F32s(core::array::from_fn(|l| entry(a, index[l] + 1)));
    let t0 = F32s(core::array::from_fn(|l| {
        entry(tables, offset[l] + index[l])
    }));
    let t1 = F32s(core::array::from_fn(|l| {
        entry(tables, offset[l] + index[l] + 1)
    }));
    t0 - (a0 - angle) * (t0 - t1) / (a0 - a1)
}

/// [`airfoil_coefficients`](fdm_core::bourg::airfoil_coefficients) lane-wise,
/// lane `l` with the tables at `offset[l]` ([`table_offset`]).
#[inline(always)]
fn airfoil_lanes(angle: L, offset: &[u32; LANES]) -> (L, L) {
    let a = &AIRFOIL_ALPHA_DEG;
    let (index, valid) = interval_lanes(a, angle);
    let cl = lerp_lanes(a, &CL_TABLES, offset, &index, angle);
    let cd = lerp_lanes(a, &CD_TABLES, offset, &index, angle);
    (
        valid.select(cl, L::splat(0.0)),
        valid.select(cd, L::splat(CD_OUTSIDE)),
    )
}

/// [`rudder_coefficients`](fdm_core::bourg::rudder_coefficients) lane-wise: the tables at `|angle|`, the lift
/// negated below 0.
#[inline(always)]
fn rudder_lanes(angle: L) -> (L, L) {
    let a = &RUDDER_ALPHA_DEG;
    let abs = angle.abs();
    let (index, valid) = interval_lanes(a, abs);
    let zero = [0; LANES];
    let cl = lerp_lanes(a, &RUDDER_CL, &zero, &index, abs);
    let cl = angle.lt(0.0).select(-cl, cl);
    let cd = lerp_lanes(a, &RUDDER_CD, &zero, &index, abs);
    (
        valid.select(cl, L::splat(0.0)),
        valid.select(cd, L::splat(CD_OUTSIDE)),
    )
}

/// `fdm_core::bourg::loads` and `step`, lane-wise, for one block.
#[inline(always)]
#[allow(clippy::too_many_lines)] // one formula per line of the scalar step
fn step_block(b: &mut Block, aircraft: &BourgAircraft, dt: f32) {
    let mass = aircraft.mass_properties();
    let elements = &aircraft.airframe().elements;
    let zero = L::splat(0.0);
    let zero3 = V3 {
        x: zero,
        y: zero,
        z: zero,
    };
    let velocity_body = V3::load(&b.velocity_body);
    let omega = V3::load(&b.angular_velocity);
    let orientation = Q4::load(&b.orientation);

    // loads: per element, in element order.
    let half = 0.5f32;
    let rho = RHO_SLUG_FT3;
    let mut carried = zero3;
    let mut stalling = [false; LANES];
    let mut fb = zero3;
    let mut mb = zero3;
    for (i, element) in elements.iter().enumerate() {
        let cg_offset = V3::splat(&mass.cg_offsets_ft[i]);
        let normal = if i == 6 {
            V3::load(&b.rudder_normal)
        } else {
            V3::splat(&mass.normals[i])
        };
        let local_velocity = velocity_body.add(omega.cross(cg_offset));
        let local_speed = local_velocity.magnitude();
        let candidate = V3 {
            x: -local_velocity.x,
            y: -local_velocity.y,
            z: -local_velocity.z,
        }
        .div(local_speed);
        carried = V3::select(local_speed.gt(1.0), candidate, carried);
        let drag = carried;
        let lift = drag.cross(normal).cross(drag).normalize();
        let s = drag.dot(normal);
        let s = s.gt(1.0).select(L::splat(1.0), s);
        let s = s.lt(-1.0).select(L::splat(-1.0), s);
        let attack_deg = s.map(asinf) * 180.0f32 / PI;
        let q_area = half * rho * local_speed * local_speed * element.area_ft2;
        let resultant = if i == 7 {
            drag.scale(L::splat(half)).scale(q_area)
        } else {
            let (cl, cd) = if i == 6 {
                rudder_lanes(attack_deg)
            } else {
                let base = airfoil_lanes(attack_deg, &b.tables[i]);
                let trimmed = Mask(b.trimmed);
                if (i == 4 || i == 5) && trimmed.any() {
                    let (cl, cd) = airfoil_lanes(attack_deg, &b.trim_tables);
                    let t = F32s(b.trim);
                    (
                        trimmed.select(base.0 + (cl - base.0) * t, base.0),
                        trimmed.select(base.1 + (cd - base.1) * t, base.1),
                    )
                } else {
                    base
                }
            };
            if i <= 3 {
                let stalled = cl.eq(0.0);
                for (flag, s) in stalling.iter_mut().zip(stalled.0) {
                    *flag |= s;
                }
            }
            lift.scale(cl).add(drag.scale(cd)).scale(q_area)
        };
        fb = fb.add(resultant);
        mb = mb.add(cg_offset.cross(resultant));
    }
    let thrust = F32s(b.thrust);
    fb = fb.add(V3 {
        x: 1.0 * thrust,
        y: 0.0 * thrust,
        z: 0.0 * thrust,
    });
    let mut force_earth = orientation.rotate(fb);
    force_earth.z = force_earth.z + G_FTPS2 * mass.mass_slug;
    let moment_body = zero3.add(mb);

    // step: semi-implicit Euler.
    let dt_l = L::splat(dt);
    let acceleration = force_earth.div(L::splat(mass.mass_slug));
    let velocity = V3::load(&b.velocity).add(acceleration.scale(dt_l));
    let position = V3::load(&b.position).add(velocity.scale(dt_l));
    let gyroscopic = omega.cross(mat_mul_vec(&mass.inertia, omega));
    let angular_velocity =
        omega.add(mat_mul_vec(&mass.inertia_inverse, moment_body.sub(gyroscopic)).scale(dt_l));
    let spin_scale = L::splat(half * dt);
    let spin = orientation.mul_vec(angular_velocity);
    let orientation = Q4 {
        w: orientation.w + spin.w * spin_scale,
        x: orientation.x + spin.x * spin_scale,
        y: orientation.y + spin.y * spin_scale,
        z: orientation.z + spin.z * spin_scale,
    };
    let norm = (orientation.w * orientation.w
        + orientation.x * orientation.x
        + orientation.y * orientation.y
        + orientation.z * orientation.z)
        .sqrt();
    let keep = norm.eq(0.0);
    let orientation = Q4 {
        w: keep.select(orientation.w, orientation.w / norm),
        x: keep.select(orientation.x, orientation.x / norm),
        y: keep.select(orientation.y, orientation.y / norm),
        z: keep.select(orientation.z, orientation.z / norm),
    };
    let velocity_body = orientation.conjugate().rotate(velocity);

    position.store(&mut b.position);
    velocity.store(&mut b.velocity);
    velocity_body.store(&mut b.velocity_body);
    angular_velocity.store(&mut b.angular_velocity);
    orientation.store(&mut b.orientation);
    b.stalling = stalling;
    let dt64 = f64::from(dt);
    for t in &mut b.time {
        *t += dt64;
    }
}

struct StepBlocks<'a> {
    blocks: &'a mut [Block],
    aircraft: &'a BourgAircraft,
    dt: f32,
    /// Whole frames with the flight status ([`BourgFleet::fly`]) rather than
    /// bare steps.
    fly: bool,
}

impl WithSimd for StepBlocks<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        if self.fly {
            for b in self.blocks {
                let saved = b.saved();
                step_block(b, self.aircraft, self.dt);
                b.settle(&saved, self.aircraft, self.dt);
            }
        } else {
            for b in self.blocks {
                step_block(b, self.aircraft, self.dt);
            }
        }
    }
}

/// A fleet of Bourg aircraft sharing one [`BourgAircraft`], each with its own
/// state and controls, stepped as structure-of-arrays, every aircraft
/// bit-identical to [`fdm_core::bourg::step`] (see the [module docs](self)).
///
/// ```
/// use fdm_core::bourg::{step, BourgAircraft, BourgControls, BourgState};
/// use fdm_fleet::bourg::BourgFleet;
///
/// let aircraft = BourgAircraft::bourg_default();
/// let controls = BourgControls::initial();
/// let mut fleet = BourgFleet::new(aircraft.clone());
/// for _ in 0..3 {
///     fleet.push(BourgState::initial(), controls);
/// }
/// let mut one = BourgState::initial();
/// for _ in 0..100 {
///     fleet.step(1.0 / 30.0);
///     one = step(&aircraft, &controls, &one, 1.0 / 30.0);
/// }
/// assert_eq!(fleet.state(2), Some(one)); // bit for bit
/// ```
#[derive(Debug, Clone)]
pub struct BourgFleet {
    aircraft: BourgAircraft,
    blocks: Vec<Block>,
    len: usize,
    arch: Arch,
}

impl BourgFleet {
    /// An empty fleet of `aircraft` (already validated by its constructor).
    /// Detects the CPU's instruction set once.
    #[must_use]
    pub fn new(aircraft: BourgAircraft) -> Self {
        Self {
            aircraft,
            blocks: Vec::new(),
            len: 0,
            arch: Arch::new(),
        }
    }

    /// Adds an aircraft; returns its index. Its flight status starts as
    /// [`FlightStatus::initial`] of its height. Nothing is checked, as in
    /// [`fdm_core::bourg::step`]: non-finite values propagate into that
    /// aircraft's lanes only.
    pub fn push(&mut self, state: BourgState, controls: BourgControls) -> usize {
        let index = self.len;
        let lane = index % LANES;
        if lane == 0 {
            self.blocks.push(Block::idle(&self.aircraft));
        }
        if let Some(block) = self.blocks.last_mut() {
            block.set_state(lane, &state);
            block.set_controls(lane, &self.aircraft, controls);
            block.status[lane] = FlightStatus::initial(Bourg::height_m(&state));
        }
        self.len += 1;
        index
    }

    /// Number of aircraft.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the fleet has no aircraft.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Aircraft `index`'s state, `None` past the end.
    #[must_use]
    pub fn state(&self, index: usize) -> Option<BourgState> {
        (index < self.len).then(|| self.blocks[index / LANES].state(index % LANES))
    }

    /// Aircraft `index`'s controls, `None` past the end.
    #[must_use]
    pub fn controls(&self, index: usize) -> Option<BourgControls> {
        (index < self.len).then(|| self.blocks[index / LANES].controls[index % LANES])
    }

    /// Every aircraft's state, in index order.
    pub fn states(&self) -> impl ExactSizeIterator<Item = BourgState> + '_ {
        (0..self.len).map(|i| self.blocks[i / LANES].state(i % LANES))
    }

    /// Replaces aircraft `index`'s state (its flight status is kept: see
    /// [`BourgFleet::set_status`]).
    ///
    /// # Errors
    /// [`crate::FleetError::OutOfRange`] past the end.
    pub fn set_state(&mut self, index: usize, state: &BourgState) -> Result<(), crate::FleetError> {
        self.check(index)?;
        self.blocks[index / LANES].set_state(index % LANES, state);
        Ok(())
    }

    /// Replaces aircraft `index`'s controls (and looks up its rudder normal
    /// and element tables again).
    ///
    /// # Errors
    /// [`crate::FleetError::OutOfRange`] past the end.
    pub fn set_controls(
        &mut self,
        index: usize,
        controls: BourgControls,
    ) -> Result<(), crate::FleetError> {
        self.check(index)?;
        self.blocks[index / LANES].set_controls(index % LANES, &self.aircraft, controls);
        Ok(())
    }

    fn check(&self, index: usize) -> Result<(), crate::FleetError> {
        if index < self.len {
            Ok(())
        } else {
            Err(crate::FleetError::OutOfRange {
                index,
                len: self.len,
            })
        }
    }

    /// Advances every aircraft by `dt` seconds (one Euler step), on this
    /// thread, with the best instruction set of this CPU: every aircraft's
    /// state becomes [`fdm_core::bourg::step`]'s, bit for bit, whatever its
    /// status (the statuses are not read or changed).
    pub fn step(&mut self, dt: f32) {
        self.run(self.arch, dt, false, false);
    }

    /// [`BourgFleet::step`] on the threads of the current rayon pool; the same
    /// bits.
    pub fn par_step(&mut self, dt: f32) {
        self.run(self.arch, dt, false, true);
    }

    /// [`BourgFleet::step`] with the kernel compiled for the SSE2 baseline.
    pub fn step_baseline(&mut self, dt: f32) {
        self.run(Arch::Scalar, dt, false, false);
    }

    /// One whole frame of every aircraft with its flight status, on this
    /// thread: each aircraft's state and status become those of
    /// [`fdm_core::model::fly`] (the model's step, then the ground contact
    /// and the touchdown; a crashed aircraft stays at rest; a step that is
    /// not finite is not kept and the aircraft is
    /// [`Diverged`](FlightStatus::Diverged) from then on), bit for bit.
    ///
    /// The kernel steps every block; the scalar `fly` or `settle` runs only
    /// for the aircraft that need it (not airborne above the ground plane,
    /// or with a component too large to be sure the state is finite), found
    /// by a lane-wise check.
    pub fn fly(&mut self, dt: f32) {
        self.run(self.arch, dt, true, false);
    }

    /// [`BourgFleet::fly`] on the threads of the current rayon pool; the same
    /// bits.
    pub fn par_fly(&mut self, dt: f32) {
        self.run(self.arch, dt, true, true);
    }

    /// [`BourgFleet::fly`] with the kernel compiled for the SSE2 baseline.
    pub fn fly_baseline(&mut self, dt: f32) {
        self.run(Arch::Scalar, dt, true, false);
    }

    fn run(&mut self, arch: Arch, dt: f32, fly: bool, parallel: bool) {
        let aircraft = &self.aircraft;
        if parallel {
            self.blocks
                .par_chunks_mut(BLOCKS_PER_TASK)
                .for_each(|blocks| {
                    arch.dispatch(StepBlocks {
                        blocks,
                        aircraft,
                        dt,
                        fly,
                    });
                });
        } else {
            arch.dispatch(StepBlocks {
                blocks: &mut self.blocks,
                aircraft,
                dt,
                fly,
            });
        }
    }

    /// `out` becomes every aircraft's position in metres (x north, y west, z
    /// up; each foot widened to `f64` and multiplied by
    /// [`METRES_PER_FOOT`](fdm_core::units::METRES_PER_FOOT), as
    /// `Bourg::view` does), in index order.
    pub fn positions_m(&self, out: &mut Vec<Vector3<f64>>) {
        use fdm_core::units::METRES_PER_FOOT;
        out.clear();
        out.extend(self.blocks.iter().flat_map(|b| {
            (0..LANES).map(move |l| {
                let p = &b.position;
                Vector3::new(
                    f64::from(p[0][l]) * METRES_PER_FOOT,
                    f64::from(p[1][l]) * METRES_PER_FOOT,
                    f64::from(p[2][l]) * METRES_PER_FOOT,
                )
            })
        }));
        out.truncate(self.len);
    }

    /// Aircraft `index`'s flight status, `None` past the end.
    #[must_use]
    pub fn status(&self, index: usize) -> Option<FlightStatus> {
        (index < self.len).then(|| self.blocks[index / LANES].status[index % LANES])
    }

    /// Every aircraft's flight status, in index order.
    pub fn statuses(&self) -> impl ExactSizeIterator<Item = FlightStatus> + '_ {
        (0..self.len).map(|i| self.blocks[i / LANES].status[i % LANES])
    }

    /// Replaces aircraft `index`'s flight status.
    ///
    /// # Errors
    /// [`crate::FleetError::OutOfRange`] past the end.
    pub fn set_status(
        &mut self,
        index: usize,
        status: FlightStatus,
    ) -> Result<(), crate::FleetError> {
        self.check(index)?;
        self.blocks[index / LANES].status[index % LANES] = status;
        Ok(())
    }

    /// The instruction set [`BourgFleet::step`] runs on, as detected at
    /// construction: `"x86-64-v4"`, `"x86-64-v3"` or `"baseline"`.
    #[must_use]
    pub const fn instruction_set(&self) -> &'static str {
        match self.arch {
            #[cfg(target_arch = "x86_64")]
            Arch::V4(_) => "x86-64-v4",
            #[cfg(target_arch = "x86_64")]
            Arch::V3(_) => "x86-64-v3",
            _ => "baseline",
        }
    }

    /// Memory per aircraft in the fleet's arrays, bytes (the last block's
    /// padding aside).
    #[must_use]
    pub const fn bytes_per_aircraft() -> usize {
        core::mem::size_of::<Block>() / LANES
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::{airfoil_coefficients, rudder_coefficients};

    fn angles() -> Vec<f32> {
        let mut v: Vec<f32> = (-4000..=4000).map(|i| i as f32 * 0.01).collect();
        // Table points, their neighbours, and the special values.
        for t in AIRFOIL_ALPHA_DEG {
            for x in [t, -t] {
                v.extend([
                    x,
                    f32::from_bits(x.to_bits() + 1),
                    f32::from_bits(x.to_bits().wrapping_sub(1)),
                ]);
            }
        }
        v.extend([
            0.0,
            -0.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
        ]);
        v
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn table_lookups_are_the_scalar_ones() {
        let flaps = [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp];
        for chunk in angles().chunks(LANES) {
            let mut lanes = [0.0; LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let flap_lanes: [Flap; LANES] = core::array::from_fn(|l| flaps[l % 3]);
            let (cl, cd) = airfoil_lanes(F32s(lanes), &flap_lanes.map(table_offset));
            let (rl, rd) = rudder_lanes(F32s(lanes));
            for l in 0..LANES {
                let (scl, scd) = airfoil_coefficients(lanes[l], flap_lanes[l]);
                assert!(
                    same(cl.0[l], scl) && same(cd.0[l], scd),
                    "{} {:?}",
                    lanes[l],
                    flap_lanes[l]
                );
                let (srl, srd) = rudder_coefficients(lanes[l]);
                assert!(
                    same(rl.0[l], srl) && same(rd.0[l], srd),
                    "rudder {}",
                    lanes[l]
                );
            }
        }
    }
}
