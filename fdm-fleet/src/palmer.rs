//! A fleet of Palmer aircraft (one shared [`PalmerAircraft`], each with its own
//! state and controls) laid out as structure-of-arrays and stepped
//! [`LANES`] aircraft per SIMD instruction.
//!
//! # Layout
//!
//! The fleet is a `Vec` of blocks of [`LANES`] aircraft ("array of structures of
//! arrays"): inside a block every field (time, x, y, z, vx, vy, vz and the
//! per-aircraft values derived from the controls) is its own `[f64; LANES]`,
//! which the kernel loads as one vector. The last block is padded with aircraft
//! at rest, stepped along and never shown, so any fleet size works; rayon hands
//! whole runs of blocks to its threads. [`PalmerFleet::bytes_per_aircraft`]
//! gives the memory per aircraft (136 bytes).
//!
//! What depends only on the aircraft and the controls (`cos`/`sin` of the bank,
//! the lift coefficient with its flap increment, `0.5 * cl`, the drag
//! coefficient, the aspect ratio, ...) is computed once when the controls are set,
//! with the scalar step's operations, instead of once per step: the same bits,
//! and the fleet's only `sin`/`cos` calls are off the per-step path.
//!
//! # The kernel is a twin of the scalar step
//!
//! [`fdm_core::palmer::step`] is the source of truth. The lane kernel below
//! evaluates every value with the same IEEE operations in the same order,
//! lane-wise (each formula carries the scalar code's grouping in its
//! parentheses, see `fdm_core`'s `palmer/dynamics.rs`); the scalar `if`s become
//! lane masks and blends: ground effect `z < 5`, the `vtotal == 0` and `vh == 0`
//! guards of the flight-path angles and the ground reaction `z <= 0 && Fz <= 0`.
//! The tests of `tests/palmer_fleet.rs` compare both, bit for bit.
//!
//! # Precisions
//!
//! * [`Precision::Exact`]: the pressure's `pow(grp, 5.25)` goes lane by lane
//!   through `fdm_core::math::pow` (glibc's `pow` through `std`), exactly as the
//!   scalar step calls it; everything else is SIMD. Every aircraft is
//!   bit-identical to [`fdm_core::palmer::step`].
//! * [`Precision::Fast`]: the `pow` becomes `x⁵ · √√x` in double-double
//!   arithmetic, all SIMD (within 1 ulp of glibc's `pow`, the same bits for
//!   99.9 % of the arguments). After 1,800 steps every aircraft is within
//!   1e-9 m and 1e-9 m/s of `Exact` (tested on the reference scenarios and
//!   random fleets of well-conditioned flights; measured at most 1e-10 m).
//!
//! # Why the instruction set cannot change the `Exact` bits
//!
//! The kernel is compiled several times and one copy is picked at run time
//! ([`pulp::Arch`]: x86-64-v4 with AVX-512, x86-64-v3 with AVX2 and FMA, or the
//! SSE2 baseline). Addition, subtraction, multiplication, division and square
//! root are correctly rounded IEEE operations in every one of these instruction
//! sets, so a lane of `vdivpd ymm` has the bits of a scalar `divsd`. The one
//! thing that could differ is fusion: `a * b + c` as one FMA rounds once instead
//! of twice. Rust never contracts a multiplication and an addition into an FMA on
//! its own (it gives LLVM no fast-math or `contract` flags, with or without the
//! `fma` target feature), and this crate never calls `mul_add`, so the FMA copy
//! computes the same roundings. glibc's `pow` is the same function whichever copy
//! calls it. The `Exact` kernel never calls `mul_add`; the `Fast` kernel calls it
//! only, where the CPU has FMA, to get the exact rounding error of a product,
//! which the baseline copy gets exactly too with Dekker's splitting, so `Fast`
//! is also the same bits on every instruction set. The tests step the same fleet
//! through the dispatched copy and the baseline copy
//! ([`PalmerFleet::step_baseline`]) and compare the bits, in both precisions.

use core::f64::consts::PI;
use core::fmt;
use core::str::FromStr;

use fdm_core::math;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::{
    AircraftError, Flaps, Palmer, PalmerAircraft, PalmerControls, PalmerState, GRAVITY_MPS2,
};
use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

use crate::fastmath::pow_5_25;
use crate::lanes::F64s;

/// Aircraft per block: the width of the lane kernel (8 f64 lanes are one
/// AVX-512 register, two AVX2 registers or four SSE2 registers).
pub const LANES: usize = 8;

/// Blocks per rayon task in [`PalmerFleet::par_step`] (`BLOCKS_PER_TASK *
/// LANES` aircraft): large enough that scheduling costs nothing next to the
/// stepping, small enough to balance two threads on a 1,000-aircraft fleet.
const BLOCKS_PER_TASK: usize = 32;

type L = F64s<LANES>;

/// How a fleet computes the pressure's `pow`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// Every aircraft bit-identical to [`fdm_core::palmer::step`] (glibc's `pow`
    /// per lane).
    #[default]
    Exact,
    /// Vectorised `pow`: every aircraft within 1e-9 m and 1e-9 m/s of
    /// [`Precision::Exact`] after 1,800 steps.
    Fast,
}

impl Precision {
    /// The name `FromStr` reads: `"exact"` or `"fast"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Fast => "fast",
        }
    }
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Precision {
    type Err = FleetError;

    /// `"exact"` or `"fast"` (as `sim-cli fleet --precision` takes them).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "exact" => Ok(Self::Exact),
            "fast" => Ok(Self::Fast),
            _ => Err(FleetError::UnknownPrecision(s.to_owned())),
        }
    }
}

/// What a fleet operation refused.
#[derive(Debug, Clone, PartialEq)]
pub enum FleetError {
    /// The shared aircraft cannot be flown ([`PalmerAircraft::validate`]).
    InvalidAircraft(AircraftError),
    /// An aircraft index past the end of the fleet.
    OutOfRange {
        /// The index asked for.
        index: usize,
        /// The fleet's size.
        len: usize,
    },
    /// A precision name other than `exact` or `fast`.
    UnknownPrecision(String),
    /// The model has no kernel of this precision (Bourg has only `exact`).
    PrecisionUnavailable {
        /// The model's name.
        model: &'static str,
        /// The precision asked for.
        precision: Precision,
    },
}

impl fmt::Display for FleetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidAircraft(err) => write!(f, "invalid aircraft: {err}"),
            Self::OutOfRange { index, len } => {
                write!(f, "aircraft {index} is out of range for a fleet of {len}")
            }
            Self::UnknownPrecision(name) => {
                write!(f, "precision must be `exact` or `fast`, got `{name}`")
            }
            Self::PrecisionUnavailable { model, precision } => {
                write!(
                    f,
                    "the {model} fleet kernel has no `{precision}` precision (use `exact`)"
                )
            }
        }
    }
}

impl std::error::Error for FleetError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::InvalidAircraft(err) => Some(err),
            _ => None,
        }
    }
}

/// The aircraft parameters the kernel reads, with the products the scalar step
/// derives from them (same operations, so the same bits).
#[derive(Debug, Clone, Copy)]
struct Shared {
    /// `pi * (span * span / area) * eff`.
    induced_drag_divisor: f64,
    /// `engine_rps * prop_diameter`.
    rps_times_diameter: f64,
    /// `mass * G`.
    weight: f64,
    mass: f64,
    cdp: f64,
    engine_power: f64,
    prop_a: f64,
    prop_b: f64,
    wing_area: f64,
}

impl Shared {
    fn new(a: &PalmerAircraft) -> Self {
        let aspect_ratio = a.wing_span_m * a.wing_span_m / a.wing_area_m2;
        Self {
            induced_drag_divisor: PI * aspect_ratio * a.eff,
            rps_times_diameter: a.engine_rps * a.prop_diameter_m,
            weight: a.mass_kg * GRAVITY_MPS2,
            mass: a.mass_kg,
            cdp: a.cdp,
            engine_power: a.engine_power_w,
            prop_a: a.prop_a,
            prop_b: a.prop_b,
            wing_area: a.wing_area_m2,
        }
    }
}

/// One aircraft's values that depend only on its controls (and the shared
/// aircraft): the scalar step's stage invariants.
#[derive(Debug, Clone, Copy)]
struct ControlTerms {
    throttle: f64,
    cos_w: f64,
    sin_w: f64,
    cl: f64,
    half_cl: f64,
    half_cd: f64,
}

impl ControlTerms {
    fn new(a: &PalmerAircraft, shared: &Shared, c: &PalmerControls) -> Self {
        let bank_rad = c.bank_deg * PI / 180.0;
        let alpha = c.alpha_deg;
        let mut cl = if alpha < a.alpha_cl_max_deg {
            a.cl_slope0_per_deg * alpha + a.cl0
        } else {
            a.cl_slope1_per_deg * alpha + a.cl1
        };
        match c.flaps {
            Flaps::Up => {}
            Flaps::Deg20 => cl += 0.25,
            Flaps::Deg40 => cl += 0.5,
        }
        Self {
            throttle: c.throttle,
            cos_w: math::cos(bank_rad),
            sin_w: math::sin(bank_rad),
            cl,
            half_cl: 0.5 * cl,
            half_cd: 0.5 * (shared.cdp + cl * cl / shared.induced_drag_divisor),
        }
    }
}

/// [`LANES`] aircraft, field by field.
#[derive(Debug, Clone, Copy)]
struct Block {
    time: [f64; LANES],
    /// `[vx, x, vy, y, vz, z]` (the scalar step's `q` order), each a lane array.
    q: [[f64; LANES]; 6],
    throttle: [f64; LANES],
    cos_w: [f64; LANES],
    sin_w: [f64; LANES],
    cl: [f64; LANES],
    half_cl: [f64; LANES],
    half_cd: [f64; LANES],
    /// The controls as set (read back by [`PalmerFleet::controls`]; the kernel
    /// reads the terms above).
    controls: [PalmerControls; LANES],
    /// Each aircraft's flight status ([`PalmerFleet::fly`]).
    status: [FlightStatus; LANES],
}

/// Beyond this magnitude a component of a stepped state sends its aircraft
/// down the scalar path of [`PalmerFleet::fly`] (which then checks
/// [`Model::is_finite`] exactly): small enough that the airspeed of a state
/// whose components are all below it cannot overflow (`3 · 1e150² <
/// f64::MAX`), so every lane not flagged is finite for the model.
const SUSPECT_F64: f64 = 1e150;

impl Block {
    /// A block of aircraft at rest, idle.
    fn idle(a: &PalmerAircraft, shared: &Shared) -> Self {
        let mut block = Self {
            time: [0.0; LANES],
            q: [[0.0; LANES]; 6],
            throttle: [0.0; LANES],
            cos_w: [0.0; LANES],
            sin_w: [0.0; LANES],
            cl: [0.0; LANES],
            half_cl: [0.0; LANES],
            half_cd: [0.0; LANES],
            controls: [PalmerControls::default(); LANES],
            status: [FlightStatus::OnGround; LANES],
        };
        for lane in 0..LANES {
            block.set_controls(lane, a, shared, PalmerControls::default());
        }
        block
    }

    fn set_state(&mut self, lane: usize, s: &PalmerState) {
        self.time[lane] = s.time_s;
        let v = [
            s.velocity_mps.x,
            s.position_m.x,
            s.velocity_mps.y,
            s.position_m.y,
            s.velocity_mps.z,
            s.position_m.z,
        ];
        for (field, value) in self.q.iter_mut().zip(v) {
            field[lane] = value;
        }
    }

    fn state(&self, lane: usize) -> PalmerState {
        Self::state_of(self.time, &self.q, lane)
    }

    /// Lane `lane`'s state in the clocks `time` and the state arrays `q`.
    fn state_of(time: [f64; LANES], q: &[[f64; LANES]; 6], lane: usize) -> PalmerState {
        let q = |j: usize| q[j][lane];
        let mut s = PalmerState::at_rest();
        s.time_s = time[lane];
        s.position_m.x = q(1);
        s.position_m.y = q(3);
        s.position_m.z = q(5);
        s.velocity_mps.x = q(0);
        s.velocity_mps.y = q(2);
        s.velocity_mps.z = q(4);
        s
    }

    /// The lanes whose stepped state may not be finite for the model: a
    /// component at or beyond [`SUSPECT_F64`] in magnitude, NaN, or a
    /// non-finite clock.
    #[inline(always)]
    fn suspect(&self) -> [bool; LANES] {
        let mut ok: [bool; LANES] = core::array::from_fn(|l| self.time[l].is_finite());
        for field in &self.q {
            for (ok, x) in ok.iter_mut().zip(field) {
                *ok &= x.abs() < SUSPECT_F64;
            }
        }
        ok.map(|ok| !ok)
    }

    /// The flight-status half of [`PalmerFleet::fly`] for a block the kernel
    /// has just stepped from `time` and `q`: every lane ends as
    /// [`fdm_core::model::fly`] would have left it (`Exact`; see
    /// [`PalmerFleet::fly`] for `Fast`).
    #[inline(always)]
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x < y)` is true for NaN, as wanted
    fn settle(&mut self, time: [f64; LANES], q: &[[f64; LANES]; 6], a: &PalmerAircraft, dt: f64) {
        // Whether any lane needs more than the step (usually none): one
        // lane-wise OR of integer flags, which vectorises.
        let mut flags = [0_u64; LANES];
        for (f, (&t, &s)) in flags.iter_mut().zip(self.time.iter().zip(&self.status)) {
            *f = u64::from(!t.is_finite()) | u64::from(s != FlightStatus::Airborne);
        }
        for (f, &z) in flags.iter_mut().zip(&self.q[5]) {
            *f |= u64::from(!(z > 0.0));
        }
        for field in &self.q {
            for (f, x) in flags.iter_mut().zip(field) {
                *f |= u64::from(!(x.abs() < SUSPECT_F64));
            }
        }
        if flags.iter().fold(0, |any, &f| any | f) == 0 {
            return;
        }
        let suspect = self.suspect();
        let airborne: [bool; LANES] = core::array::from_fn(|l| {
            (self.status[l] == FlightStatus::Airborne) & (self.q[5][l] > 0.0) & !suspect[l]
        });
        self.settle_lanes(&airborne, &suspect, time, q, a, dt);
    }

    /// The scalar part of [`Self::settle`], for the lanes not `airborne`
    /// (rare: out of the hot loop).
    #[cold]
    #[inline(never)]
    fn settle_lanes(
        &mut self,
        airborne: &[bool; LANES],
        suspect: &[bool; LANES],
        time: [f64; LANES],
        q: &[[f64; LANES]; 6],
        a: &PalmerAircraft,
        dt: f64,
    ) {
        for lane in 0..LANES {
            let status = self.status[lane];
            if airborne[lane] {
                continue;
            }
            let (state, status) = crate::finish_lane::<Palmer>(
                a,
                &self.controls[lane],
                status,
                suspect[lane],
                || Self::state_of(time, q, lane),
                || self.state(lane),
                dt,
            );
            self.set_state(lane, &state);
            self.status[lane] = status;
        }
    }

    fn set_controls(
        &mut self,
        lane: usize,
        a: &PalmerAircraft,
        shared: &Shared,
        c: PalmerControls,
    ) {
        let t = ControlTerms::new(a, shared, &c);
        self.throttle[lane] = t.throttle;
        self.cos_w[lane] = t.cos_w;
        self.sin_w[lane] = t.sin_w;
        self.cl[lane] = t.cl;
        self.half_cl[lane] = t.half_cl;
        self.half_cd[lane] = t.half_cd;
        self.controls[lane] = c;
    }
}

/// The per-block constants of one step, loaded as lanes.
struct Terms {
    throttle: L,
    cos_w: L,
    sin_w: L,
    cl: L,
    half_cl: L,
    half_cd: L,
}

/// Step 4's pressure `101325 * pow(1 - 0.0065 * z / 288.15, 5.25)`.
#[inline(always)]
fn pressure<const FAST: bool, const FMA: bool>(z: L) -> L {
    let grp = 1.0 - 0.0065 * z / 288.15;
    let power = if FAST {
        pow_5_25::<LANES, FMA>(grp)
    } else {
        grp.map(|x| math::pow(x, 5.25))
    };
    101_325.0 * power
}

/// The scalar step's `rhs(q, delta_q, ds, q_scale)`, lane-wise (steps 2–13).
/// Returns `dq` in `q` order; `dq[1]` and `dq[3]` (`ds * vx`, `ds * vy`) are
/// included since the RK sum needs them.
#[inline(always)]
#[allow(clippy::similar_names)] // cos_w/cos_p/cos_t as in the spec
fn rhs<const FAST: bool, const FMA: bool>(
    sh: &Shared,
    k: &Terms,
    q: &[L; 6],
    delta_q: &[L; 6],
    ds: f64,
    q_scale: f64,
) -> [L; 6] {
    // Step 2 (x and y of the intermediate state are never read).
    let vx = q[0] + q_scale * delta_q[0];
    let vy = q[2] + q_scale * delta_q[2];
    let vz = q[4] + q_scale * delta_q[4];
    let z = q[5] + q_scale * delta_q[5];
    // Step 3.
    let vh = (vx * vx + vy * vy).sqrt();
    let vtotal = (vx * vx + vy * vy + vz * vz).sqrt();
    // Step 4.
    let pressure = pressure::<FAST, FMA>(z);
    let temperature = 288.15 - 0.0065 * z;
    let density = 0.00348 * pressure / temperature;
    // Step 5.
    let omega = density / 1.225;
    let factor = (omega - 0.12) / 0.88;
    // Step 6.
    let advance_ratio = vtotal / sh.rps_times_diameter;
    let thrust = k.throttle
        * factor
        * sh.engine_power
        * (sh.prop_a + sh.prop_b * advance_ratio * advance_ratio)
        / sh.rps_times_diameter;
    // Step 7: ground effect below 5 m, as a blend (computed only when a lane
    // of the block is that low).
    let low = z.lt(5.0);
    let (half_cl, half_cd) = if low.any() {
        let cl = k.cl + 0.25;
        let half_cl = 0.5 * cl;
        let half_cd = 0.5 * (sh.cdp + cl * cl / sh.induced_drag_divisor);
        (
            low.select(half_cl, k.half_cl),
            low.select(half_cd, k.half_cd),
        )
    } else {
        (k.half_cl, k.half_cd)
    };
    // Steps 8 and 9 (`vtotal^2` multiplied in place).
    let lift = half_cl * density * vtotal * vtotal * sh.wing_area;
    let drag = half_cd * density * vtotal * vtotal * sh.wing_area;
    // Step 10 (the divisions of a zero speed give NaN in lanes the blend drops).
    let still = vtotal.eq(0.0);
    let cos_p = still.select(L::splat(1.0), vh / vtotal);
    let sin_p = still.select(L::splat(0.0), vz / vtotal);
    let vertical = vh.eq(0.0);
    let cos_t = vertical.select(L::splat(1.0), vx / vh);
    let sin_t = vertical.select(L::splat(0.0), vy / vh);
    let (cos_w, sin_w) = (k.cos_w, k.sin_w);
    // Step 11.
    let fx = cos_t * cos_p * (thrust - drag) + (sin_t * sin_w - cos_t * sin_p * cos_w) * lift;
    let fy = sin_t * cos_p * (thrust - drag) + (-cos_t * sin_w - sin_t * sin_p * cos_w) * lift;
    let fz = sin_p * (thrust - drag) + cos_p * cos_w * lift;
    let fz = fz + sh.weight;
    // Step 12.
    let fz = z.le(0.0).and(fz.le(0.0)).select(L::splat(0.0), fz);
    // Step 13.
    let mass = sh.mass;
    [
        ds * (fx / mass),
        ds * vx,
        ds * (fy / mass),
        ds * vy,
        ds * (fz / mass),
        ds * vz,
    ]
}

/// One RK4 step of one block (the scalar `step`, lane-wise).
#[inline(always)]
fn step_block<const FAST: bool, const FMA: bool>(b: &mut Block, sh: &Shared, ds: f64) {
    let k = Terms {
        throttle: F64s(b.throttle),
        cos_w: F64s(b.cos_w),
        sin_w: F64s(b.sin_w),
        cl: F64s(b.cl),
        half_cl: F64s(b.half_cl),
        half_cd: F64s(b.half_cd),
    };
    let q: [L; 6] = core::array::from_fn(|j| F64s(b.q[j]));
    let dq1 = rhs::<FAST, FMA>(sh, &k, &q, &q, ds, 0.0);
    let dq2 = rhs::<FAST, FMA>(sh, &k, &q, &dq1, ds, 0.5);
    let dq3 = rhs::<FAST, FMA>(sh, &k, &q, &dq2, ds, 0.5);
    let dq4 = rhs::<FAST, FMA>(sh, &k, &q, &dq3, ds, 1.0);
    for j in 0..6 {
        b.q[j] = (q[j] + (dq1[j] + 2.0 * dq2[j] + 2.0 * dq3[j] + dq4[j]) / 6.0).0;
    }
    b.time = (F64s(b.time) + ds).0;
}

/// The stepping loop over some blocks, generic over the instruction set pulp
/// picked: `with_simd` and everything it calls are inlined into pulp's
/// `#[target_feature]` function, so the lane loops compile to that set.
struct StepBlocks<'a> {
    blocks: &'a mut [Block],
    shared: &'a Shared,
    ds: f64,
    precision: Precision,
    /// Whether the instruction set has FMA (used only for the exact product
    /// errors of the fast `pow`, see `fastmath`).
    fma: bool,
    /// Whole frames with the flight status ([`PalmerFleet::fly`]) rather than
    /// bare steps.
    fly: Option<&'a PalmerAircraft>,
}

impl WithSimd for StepBlocks<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        match (self.precision, self.fma) {
            (Precision::Exact, _) => self.each::<false, false>(),
            (Precision::Fast, false) => self.each::<true, false>(),
            (Precision::Fast, true) => self.each::<true, true>(),
        }
    }
}

impl StepBlocks<'_> {
    /// The kernel on every block, each followed by its flight status with
    /// [`Self::fly`].
    #[inline(always)]
    fn each<const FAST: bool, const FMA: bool>(self) {
        let step = step_block::<FAST, FMA>;
        let (shared, ds) = (self.shared, self.ds);
        if let Some(aircraft) = self.fly {
            for b in self.blocks {
                let (time, q) = (b.time, b.q);
                step(b, shared, ds);
                b.settle(time, &q, aircraft, ds);
            }
        } else {
            for b in self.blocks {
                step(b, shared, ds);
            }
        }
    }
}

/// Whether `arch` has FMA instructions (x86-64-v3 and v4 do; the baseline and
/// other architectures are treated as not having them, which is always correct,
/// only slower).
const fn has_fma(arch: Arch) -> bool {
    match arch {
        #[cfg(target_arch = "x86_64")]
        Arch::V4(_) | Arch::V3(_) => true,
        _ => false,
    }
}

/// A fleet of Palmer aircraft sharing one [`PalmerAircraft`], each with its own
/// state and controls, stepped as structure-of-arrays (see the [module
/// docs](self)).
///
/// ```
/// use fdm_core::palmer::{step, PalmerAircraft, PalmerControls, PalmerState};
/// use fdm_fleet::palmer::{PalmerFleet, Precision};
///
/// let cessna = PalmerAircraft::cessna_172();
/// let controls = PalmerControls { throttle: 1.0, alpha_deg: 4.0, ..PalmerControls::default() };
/// let mut fleet = PalmerFleet::new(cessna)?;
/// for _ in 0..10 {
///     fleet.push(PalmerState::at_rest(), controls);
/// }
/// let mut one = PalmerState::at_rest();
/// for _ in 0..100 {
///     fleet.step(0.1, Precision::Exact);
///     one = step(&cessna, &controls, &one, 0.1);
/// }
/// assert_eq!(fleet.state(9), Some(one)); // bit for bit
/// # Ok::<(), fdm_fleet::palmer::FleetError>(())
/// ```
#[derive(Debug, Clone)]
pub struct PalmerFleet {
    aircraft: PalmerAircraft,
    shared: Shared,
    blocks: Vec<Block>,
    len: usize,
    arch: Arch,
}

impl PalmerFleet {
    /// An empty fleet of `aircraft`, which must pass
    /// [`PalmerAircraft::validate`]. Detects the CPU's instruction set once.
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the parameters cannot be flown.
    pub fn new(aircraft: PalmerAircraft) -> Result<Self, FleetError> {
        aircraft.validate().map_err(FleetError::InvalidAircraft)?;
        Ok(Self {
            shared: Shared::new(&aircraft),
            aircraft,
            blocks: Vec::new(),
            len: 0,
            arch: Arch::new(),
        })
    }

    /// A fleet of `aircraft` flying the given states and controls, in order.
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the parameters cannot be flown.
    pub fn from_states(
        aircraft: PalmerAircraft,
        members: impl IntoIterator<Item = (PalmerState, PalmerControls)>,
    ) -> Result<Self, FleetError> {
        let mut fleet = Self::new(aircraft)?;
        for (state, controls) in members {
            fleet.push(state, controls);
        }
        Ok(fleet)
    }

    /// Adds an aircraft; returns its index. Its flight status starts as
    /// [`FlightStatus::initial`] of its height. States and controls are not
    /// checked, as in [`fdm_core::palmer::step`]: non-finite values propagate
    /// into that aircraft's lanes only.
    pub fn push(&mut self, state: PalmerState, controls: PalmerControls) -> usize {
        let index = self.len;
        let lane = index % LANES;
        if lane == 0 {
            self.blocks.push(Block::idle(&self.aircraft, &self.shared));
        }
        let (aircraft, shared) = (self.aircraft, self.shared);
        if let Some(block) = self.blocks.last_mut() {
            block.set_state(lane, &state);
            block.set_controls(lane, &aircraft, &shared, controls);
            block.status[lane] = FlightStatus::initial(Palmer::height_m(&state));
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

    /// The shared aircraft parameters.
    #[must_use]
    pub const fn aircraft(&self) -> &PalmerAircraft {
        &self.aircraft
    }

    /// Aircraft `index`'s state, `None` past the end.
    #[must_use]
    pub fn state(&self, index: usize) -> Option<PalmerState> {
        (index < self.len).then(|| self.blocks[index / LANES].state(index % LANES))
    }

    /// Aircraft `index`'s controls, `None` past the end.
    #[must_use]
    pub fn controls(&self, index: usize) -> Option<PalmerControls> {
        (index < self.len).then(|| self.blocks[index / LANES].controls[index % LANES])
    }

    /// Every aircraft's state, in index order.
    pub fn states(&self) -> impl ExactSizeIterator<Item = PalmerState> + '_ {
        (0..self.len).map(|i| self.blocks[i / LANES].state(i % LANES))
    }

    fn check(&self, index: usize) -> Result<(), FleetError> {
        if index < self.len {
            Ok(())
        } else {
            Err(FleetError::OutOfRange {
                index,
                len: self.len,
            })
        }
    }

    /// Replaces aircraft `index`'s state (its flight status is kept: see
    /// [`PalmerFleet::set_status`]).
    ///
    /// # Errors
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_state(&mut self, index: usize, state: &PalmerState) -> Result<(), FleetError> {
        self.check(index)?;
        self.blocks[index / LANES].set_state(index % LANES, state);
        Ok(())
    }

    /// Replaces aircraft `index`'s controls (and recomputes its control terms:
    /// one scalar `sin` and `cos`).
    ///
    /// # Errors
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_controls(
        &mut self,
        index: usize,
        controls: PalmerControls,
    ) -> Result<(), FleetError> {
        self.check(index)?;
        let (aircraft, shared) = (self.aircraft, self.shared);
        self.blocks[index / LANES].set_controls(index % LANES, &aircraft, &shared, controls);
        Ok(())
    }

    /// Advances every aircraft by `dt_s` with one RK4 step, on this thread, with
    /// the best instruction set of this CPU. Like [`fdm_core::palmer::step`] it
    /// checks nothing: a non-finite `dt_s` makes every state non-finite. The
    /// statuses are not read or changed.
    pub fn step(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch, dt_s, precision, false, false);
    }

    /// [`PalmerFleet::step`] on the threads of the current rayon pool (the
    /// global pool, or the one `ThreadPool::install` runs in), in runs of
    /// 256 aircraft. The results are the same bits as [`PalmerFleet::step`]:
    /// each aircraft is stepped by the same code whichever thread takes it.
    pub fn par_step(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch, dt_s, precision, false, true);
    }

    /// [`PalmerFleet::step`] with the kernel compiled for the SSE2 baseline,
    /// whatever the CPU has: for comparing instruction sets (the tests check
    /// that it gives the same bits as the dispatched kernel).
    pub fn step_baseline(&mut self, dt_s: f64, precision: Precision) {
        self.run(Arch::Scalar, dt_s, precision, false, false);
    }

    /// One whole frame of every aircraft with its flight status, on this
    /// thread. In [`Precision::Exact`] each aircraft's state and status become
    /// those of [`fdm_core::model::fly`], bit for bit (the model's step, then
    /// the ground contact and the touchdown; a crashed aircraft stays at
    /// rest; a step that is not finite is not kept and the aircraft is
    /// [`Diverged`](FlightStatus::Diverged) from then on).
    ///
    /// The kernel steps every block; the scalar `fly` or `settle` runs only
    /// for the aircraft that need it (not airborne above the ground plane,
    /// or with a component too large to be sure the state is finite), found
    /// by a lane-wise check. In [`Precision::Fast`] the aircraft the scalar
    /// `fly` takes (crashed, diverged, or with such a large component) get the
    /// exact step for that frame.
    pub fn fly(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch, dt_s, precision, true, false);
    }

    /// [`PalmerFleet::fly`] on the threads of the current rayon pool; the
    /// same bits.
    pub fn par_fly(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch, dt_s, precision, true, true);
    }

    /// [`PalmerFleet::fly`] with the kernel compiled for the SSE2 baseline.
    pub fn fly_baseline(&mut self, dt_s: f64, precision: Precision) {
        self.run(Arch::Scalar, dt_s, precision, true, false);
    }

    fn run(&mut self, arch: Arch, ds: f64, precision: Precision, fly: bool, parallel: bool) {
        let (shared, aircraft) = (&self.shared, &self.aircraft);
        let fly = fly.then_some(aircraft);
        let fma = has_fma(arch);
        if parallel {
            self.blocks
                .par_chunks_mut(BLOCKS_PER_TASK)
                .for_each(|blocks| {
                    arch.dispatch(StepBlocks {
                        blocks,
                        shared,
                        ds,
                        precision,
                        fma,
                        fly,
                    });
                });
        } else {
            arch.dispatch(StepBlocks {
                blocks: &mut self.blocks,
                shared,
                ds,
                precision,
                fma,
                fly,
            });
        }
    }

    /// `out` becomes every aircraft's position, metres (x north, y west, z
    /// up), in index order.
    pub fn positions_m(&self, out: &mut Vec<fdm_core::bourg::Vector3<f64>>) {
        out.clear();
        out.extend(self.blocks.iter().flat_map(|b| {
            (0..LANES).map(move |l| fdm_core::bourg::Vector3::new(b.q[1][l], b.q[3][l], b.q[5][l]))
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
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_status(&mut self, index: usize, status: FlightStatus) -> Result<(), FleetError> {
        self.check(index)?;
        self.blocks[index / LANES].status[index % LANES] = status;
        Ok(())
    }

    /// The instruction set [`PalmerFleet::step`] runs on, as detected at
    /// construction: `"x86-64-v4"` (AVX-512), `"x86-64-v3"` (AVX2 and FMA) or
    /// `"baseline"` (SSE2 on x86-64, or another architecture's default).
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
    /// padding aside): the seven state values, six control terms and the
    /// controls as set.
    #[must_use]
    pub const fn bytes_per_aircraft() -> usize {
        core::mem::size_of::<Block>() / LANES
    }

    /// Memory the fleet's arrays take now, bytes (whole blocks, padding
    /// included; the `Vec`'s spare capacity not counted).
    #[must_use]
    pub const fn bytes(&self) -> usize {
        self.blocks.len() * core::mem::size_of::<Block>()
    }
}
