//! Bourg's step in lanes: the [`LaneModel`] seam a structure-of-arrays fleet
//! flies it through. The physics is [`super::generic`]'s, the one source of
//! the scalar [`step`](super::step), instantiated with [`F32s`] lanes; this
//! module adds only the lanes' table look-ups (the [`BourgReal`] hooks) and
//! the moves of one aircraft in and out of a block.
//!
//! # The table look-ups in lanes
//!
//! The airfoil and rudder look-ups ([`airfoil_coefficients`],
//! [`rudder_coefficients`]) search the interval of the angle and interpolate.
//! In lanes they read no memory by lane: the tables are nine (rudder: seven)
//! constants. The comparisons `a[j] <= angle` give one mask per abscissa;
//! a lane's interval `i` is the last `j` set (see [`at_or_above`]). Its
//! entries `t[i]`, `t[i + 1]` and abscissa `a[i]` are fetched in one of two
//! ways, with the same bits (a fetch moves an entry, it computes nothing):
//!
//! * by permutes, where the fleet kernel's instruction set has them
//!   ([`Permutes`]: AVX-512's `vpermt2ps`, 16 lanes out of 32 entries in two
//!   registers). The three airfoil tables of a coefficient are laid end to
//!   end (27 entries), a lane's index is its flap's offset plus `i`, `i`
//!   being the count of the masks set (they are nested, as `a` increases
//!   strictly): five permutes per look-up (`t[i]`, `t[i + 1]` of CL and CD,
//!   and `a[i]`) instead of about seventy selects, which on Intel share the
//!   two 512-bit ports with the rest of the step (BENCHMARKS.md, "Bourg's
//!   look-ups by permutes");
//! * by selects elsewhere (AVX2, the baseline, other architectures, and
//!   [`LaneModel::step_lanes`]): entry 0 (1), replaced by entry `j`
//!   (`j + 1`) in the lanes at or above `a[j]`, `j` rising; a lane's flap
//!   (of three) picks its table's entry `j` by two more selects, before the
//!   interval's.
//!
//! The interpolation is the scalar formula, lane-wise, except that the
//! division by `a[i] − a[i + 1]`, always −4 (checked at compile time), is
//! the multiplication by −1/4: the same bits, as both round the same real
//! number. The unit tests below compare every lane of both forms with the
//! scalar functions bit for bit (every `f32` near the abscissae, a stride
//! through −25..25 and random bit patterns, each flap in mixed and uniform
//! blocks). Before the selects, a lane's table was an offset into the three
//! tables laid end to end and its entries gathers (`vgatherdps`, microcoded
//! on the project's CPU; BENCHMARKS.md, "Bourg's look-ups without
//! gathers").
//!
//! | fleet block | lanes | read by the step | written by the step |
//! |---|---|---|---|
//! | `Vars` | [`BourgVars`] of [`BourgLanes`] | all but `stalling` | all |
//! | `Terms` | [`BourgTerms`] of each lane's controls | all | never (set with the controls) |
//! | `Shared` | nothing: the aircraft's mass properties are read in place | | |

use nalgebra::Vector3;

#[cfg(doc)]
use super::airfoil::{airfoil_coefficients, rudder_coefficients};
use super::airfoil::{
    AIRFOIL_ALPHA_DEG, CD_NEUTRAL, CD_OUTSIDE, CD_TRAILING_EDGE_DOWN, CD_TRAILING_EDGE_UP,
    CL_NEUTRAL, CL_TRAILING_EDGE_DOWN, CL_TRAILING_EDGE_UP, RUDDER_ALPHA_DEG, RUDDER_CD, RUDDER_CL,
};
use super::airframe::{BourgAircraft, Flap};
use super::controls::BourgControls;
use super::generic::{self, BourgReal, BourgTerms, BourgVars};
use super::model::{state_of, vars};
use super::{Bourg, BourgState};

use crate::real::{F32s, LaneMask, LaneModel, Maths, NoPermutes, Permutes, Real, V3};

/// Aircraft per block of a Bourg fleet: 16 `f32` lanes (one AVX-512 register,
/// two AVX2 ones).
pub const LANES: usize = 16;

/// The lane vector of a Bourg fleet.
pub type BourgLanes = F32s<LANES>;

/// Whether `a[i] − a[i + 1]`, computed in `f32` as the scalar look-up does,
/// is exactly `−STEP_DEG` in every interval of the abscissae `a`: then the
/// look-ups' division by it is the multiplication by [`INVERSE_STEP`].
const fn evenly_spaced(a: &[f32]) -> bool {
    let mut i = 0;
    while i + 1 < a.len() {
        if a[i] - a[i + 1] != -STEP_DEG {
            return false;
        }
        i += 1;
    }
    true
}

/// The spacing of the airfoil and rudder abscissae, degrees.
const STEP_DEG: f32 = 4.0;
/// `1 / (a[i] − a[i + 1])`: `−1/4`, exact, so `x / (a[i] − a[i + 1])` and
/// `x * INVERSE_STEP` round the same real number, to the same bits (a
/// division by a power of two, for every `x` including subnormals, zeros,
/// infinities and NaN).
const INVERSE_STEP: f32 = -1.0 / STEP_DEG;
const _: () = assert!(evenly_spaced(&AIRFOIL_ALPHA_DEG) && evenly_spaced(&RUDDER_ALPHA_DEG));
const _: () = assert!(INVERSE_STEP * -STEP_DEG == 1.0);

/// For each abscissa `a[j]`, the lanes with `a[j] <= angle` (none for NaN).
/// The scalar look-up's interval `i` (the first with `a[i] <= angle <
/// a[i + 1]`) is the last `j` set, as `a` increases strictly; it exists
/// exactly when `a[0] <= angle < a[last]`, the returned mask.
#[inline(always)]
fn at_or_above<const T: usize, const N: usize>(
    a: &[f32; T],
    angle: F32s<N>,
) -> ([LaneMask<N>; T], LaneMask<N>) {
    // A loop, not `core::array::from_fn`, which the compiler kept out of
    // line here (a call per abscissa).
    let mut at_or_above = [LaneMask([false; N]); T];
    for (m, &x) in at_or_above.iter_mut().zip(a) {
        *m = LaneMask(each_lane!(N, |l| x <= angle.0[l]));
    }
    let valid = LaneMask(each_lane!(N, |l| a[0] <= angle.0[l] && angle.0[l] < a[T - 1]));
    (at_or_above, valid)
}

/// `(column(i), column(i + 1))` in each lane's interval `i` (see
/// [`at_or_above`]), by selects: `column(0)` (`column(1)`), replaced by
/// `column(j)` (`column(j + 1)`) in the lanes at or above `a[j]`, `j` rising
/// to the last interval. (Lanes outside the table get an interval's entries
/// too; the look-ups discard them.)
#[inline(always)]
fn pick<const T: usize, const N: usize>(
    at_or_above: &[LaneMask<N>; T],
    column: impl Fn(usize) -> F32s<N>,
) -> (F32s<N>, F32s<N>) {
    let mut t0 = column(0);
    let mut t1 = column(1);
    for (j, &m) in at_or_above.iter().enumerate().take(T - 1).skip(1) {
        t0 = F32s::select(m, column(j), t0);
        t1 = F32s::select(m, column(j + 1), t1);
    }
    (t0, t1)
}

/// The scalar `lerp` in each lane's interval `i`:
/// `t[i] - (a[i] - angle) * (t[i] - t[i+1]) / (a[i] - a[i+1])`, with
/// `t0 = t[i]`, `t1 = t[i + 1]` and `a0 = a[i]` given and the division the
/// exact multiplication by [`INVERSE_STEP`].
#[inline(always)]
fn lerp<const N: usize>(t0: F32s<N>, t1: F32s<N>, a0: F32s<N>, angle: F32s<N>) -> F32s<N> {
    t0 - (a0 - angle) * (t0 - t1) * INVERSE_STEP
}

/// [`lerp`] with `t[i]`, `t[i + 1]` picked from `column` by [`pick`], lane
/// `l`'s table entry `j` being `column(j).0[l]`.
#[inline(always)]
fn lerp_lanes<const T: usize, const N: usize>(
    at_or_above: &[LaneMask<N>; T],
    a0: F32s<N>,
    column: impl Fn(usize) -> F32s<N>,
    angle: F32s<N>,
) -> F32s<N> {
    let (t0, t1) = pick(at_or_above, column);
    lerp(t0, t1, a0, angle)
}

/// Each lane's interval `i` as an index: the number of the masks
/// `a[1] <= angle`, ..., `a[T − 2] <= angle` set. They are nested (`a`
/// increases strictly), so this is the last `j` set, or 0: the interval
/// whose entries [`pick`] ends on, in every lane (NaN, outside the table and
/// the boundaries included).
#[inline(always)]
fn interval<const T: usize, const N: usize>(at_or_above: &[LaneMask<N>; T]) -> [u32; N] {
    let mut i = [0_u32; N];
    for m in &at_or_above[1..T - 1] {
        i = each_lane!(N, |l| i[l] + u32::from(m.0[l]));
    }
    i
}

/// `entries` at `at` in a table of 32 `f32` (zeros after them): what the
/// permutes read.
const fn table_32(mut table: [f32; 32], at: usize, entries: &[f32]) -> [f32; 32] {
    let mut j = 0;
    while j < entries.len() {
        table[at + j] = entries[j];
        j += 1;
    }
    table
}

/// A coefficient's three airfoil tables laid end to end, flap `f`'s at
/// `AIRFOIL_TABLE * f as usize` (the enum's discriminant).
const fn airfoil_tables(down: &[f32; 9], neutral: &[f32; 9], up: &[f32; 9]) -> [f32; 32] {
    let t = table_32(
        [0.0; 32],
        AIRFOIL_TABLE * Flap::TrailingEdgeDown as usize,
        down,
    );
    let t = table_32(t, AIRFOIL_TABLE * Flap::Neutral as usize, neutral);
    table_32(t, AIRFOIL_TABLE * Flap::TrailingEdgeUp as usize, up)
}

/// The length of an airfoil table.
const AIRFOIL_TABLE: usize = AIRFOIL_ALPHA_DEG.len();
/// The airfoil abscissae, for the permutes.
const AIRFOIL_A_32: [f32; 32] = table_32([0.0; 32], 0, &AIRFOIL_ALPHA_DEG);
/// The three CL tables, for the permutes.
const AIRFOIL_CL_32: [f32; 32] =
    airfoil_tables(&CL_TRAILING_EDGE_DOWN, &CL_NEUTRAL, &CL_TRAILING_EDGE_UP);
/// The three CD tables, for the permutes.
const AIRFOIL_CD_32: [f32; 32] =
    airfoil_tables(&CD_TRAILING_EDGE_DOWN, &CD_NEUTRAL, &CD_TRAILING_EDGE_UP);
/// Where the rudder's CD starts in [`RUDDER_32`] (CL at 0).
const RUDDER_CD_AT: u32 = 8;
/// Where the rudder's abscissae start in [`RUDDER_32`].
const RUDDER_A_AT: u32 = 16;
/// The rudder's CL, CD and abscissae in one table, for the permutes.
const RUDDER_32: [f32; 32] = table_32(
    table_32(
        table_32([0.0; 32], 0, &RUDDER_CL),
        RUDDER_CD_AT as usize,
        &RUDDER_CD,
    ),
    RUDDER_A_AT as usize,
    &RUDDER_ALPHA_DEG,
);
const _: () = assert!(
    3 * AIRFOIL_TABLE <= 32
        && RUDDER_CL.len() <= RUDDER_CD_AT as usize
        && RUDDER_CD_AT as usize + RUDDER_CD.len() <= RUDDER_A_AT as usize
        && RUDDER_A_AT as usize + RUDDER_ALPHA_DEG.len() <= 32
);

/// [`lerp`] of each lane's entries `at`, `at + 1` of `table`, fetched by
/// `permutes` (`None` if the instruction set has none). A function, not a
/// closure: the compiler kept such closures out of line, compiled for the
/// baseline instruction set, each permute a call.
#[inline(always)]
fn lerp_permuted<P: Permutes, const N: usize>(
    permutes: P,
    table: &[f32; 32],
    at: [u32; N],
    a0: F32s<N>,
    angle: F32s<N>,
) -> Option<F32s<N>> {
    let next = each_lane!(N, |l| at[l] + 1);
    Some(lerp(
        F32s(permutes.permute_32(table, at)?),
        F32s(permutes.permute_32(table, next)?),
        a0,
        angle,
    ))
}

/// The airfoil look-up's CL and CD in each lane (before the lanes outside
/// the table are set), their entries fetched by `permutes`; `None` if the
/// instruction set has none (the caller's selects).
#[inline(always)]
fn airfoil_permuted<P: Permutes, const N: usize>(
    permutes: P,
    at_or_above: &[LaneMask<N>; AIRFOIL_TABLE],
    angle: F32s<N>,
    flaps: [Flap; N],
) -> Option<(F32s<N>, F32s<N>)> {
    let i = interval(at_or_above);
    let a0 = F32s(permutes.permute_32(&AIRFOIL_A_32, i)?);
    // A lane's entry `i` in its flap's table.
    let at = each_lane!(N, |l| AIRFOIL_TABLE as u32 * flaps[l] as u32 + i[l]);
    Some((
        lerp_permuted(permutes, &AIRFOIL_CL_32, at, a0, angle)?,
        lerp_permuted(permutes, &AIRFOIL_CD_32, at, a0, angle)?,
    ))
}

/// The rudder look-up's CL (of `|angle|`, before the sign) and CD in each
/// lane (before the lanes outside the table are set), their entries fetched
/// by `permutes`; `None` if the instruction set has none.
#[inline(always)]
fn rudder_permuted<P: Permutes, const N: usize>(
    permutes: P,
    at_or_above: &[LaneMask<N>; 7],
    abs: F32s<N>,
) -> Option<(F32s<N>, F32s<N>)> {
    let i = interval(at_or_above);
    let a_at = each_lane!(N, |l| i[l] + RUDDER_A_AT);
    let a0 = F32s(permutes.permute_32(&RUDDER_32, a_at)?);
    let cd_at = each_lane!(N, |l| i[l] + RUDDER_CD_AT);
    Some((
        lerp_permuted(permutes, &RUDDER_32, i, a0, abs)?,
        lerp_permuted(permutes, &RUDDER_32, cd_at, a0, abs)?,
    ))
}

impl<const N: usize> BourgReal for F32s<N> {
    /// Each lane's flap setting.
    type Table = [Flap; N];

    #[inline(always)]
    fn table(flap: Flap) -> [Flap; N] {
        [flap; N]
    }

    #[inline(always)]
    fn set_table_lane(table: &mut [Flap; N], i: usize, flap: Flap) {
        table[i] = flap;
    }

    #[inline(always)]
    fn airfoil<P: Permutes>(angle: Self, flaps: [Flap; N], permutes: P) -> (Self, Self) {
        let a = &AIRFOIL_ALPHA_DEG;
        let (at_or_above, valid) = at_or_above(a, angle);
        // A `match`, not `unwrap_or_else`: no closure to be kept out of line.
        let (cl, cd) = match airfoil_permuted(permutes, &at_or_above, angle, flaps) {
            Some(permuted) => permuted,
            None => airfoil_selected(&at_or_above, angle, flaps),
        };
        (
            Self::select(valid, cl, Self::splat(0.0)),
            Self::select(valid, cd, Self::splat(CD_OUTSIDE)),
        )
    }

    #[inline(always)]
    fn rudder<P: Permutes>(angle: Self, permutes: P) -> (Self, Self) {
        let a = &RUDDER_ALPHA_DEG;
        let abs = angle.abs();
        let (at_or_above, valid) = at_or_above(a, abs);
        let (cl, cd) = match rudder_permuted(permutes, &at_or_above, abs) {
            Some(permuted) => permuted,
            None => rudder_selected(&at_or_above, abs),
        };
        let cl = Self::select(angle.lt(0.0), -cl, cl);
        (
            Self::select(valid, cl, Self::splat(0.0)),
            Self::select(valid, cd, Self::splat(CD_OUTSIDE)),
        )
    }
}

/// The airfoil look-up's CL and CD in each lane (before the lanes outside
/// the table are set), their entries picked by selects.
#[inline(always)]
fn airfoil_selected<const N: usize>(
    at_or_above: &[LaneMask<N>; AIRFOIL_TABLE],
    angle: F32s<N>,
    flaps: [Flap; N],
) -> (F32s<N>, F32s<N>) {
    let a = &AIRFOIL_ALPHA_DEG;
    let (a0, _) = pick(at_or_above, |j| F32s::splat(a[j]));
    let down = LaneMask(each_lane!(N, |l| flaps[l] == Flap::TrailingEdgeDown));
    let up = LaneMask(each_lane!(N, |l| flaps[l] == Flap::TrailingEdgeUp));
    // Entry `j` of each lane's table of the three.
    let column = |neutral: &[f32; 9], te_down: &[f32; 9], te_up: &[f32; 9], j: usize| {
        let c = F32s::select(up, F32s::splat(te_up[j]), F32s::splat(neutral[j]));
        F32s::select(down, F32s::splat(te_down[j]), c)
    };
    let cl = lerp_lanes(
        at_or_above,
        a0,
        |j| column(&CL_NEUTRAL, &CL_TRAILING_EDGE_DOWN, &CL_TRAILING_EDGE_UP, j),
        angle,
    );
    let cd = lerp_lanes(
        at_or_above,
        a0,
        |j| column(&CD_NEUTRAL, &CD_TRAILING_EDGE_DOWN, &CD_TRAILING_EDGE_UP, j),
        angle,
    );
    (cl, cd)
}

/// The rudder look-up's CL (of `|angle|`, before the sign) and CD in each
/// lane (before the lanes outside the table are set), their entries picked
/// by selects.
#[inline(always)]
fn rudder_selected<const N: usize>(
    at_or_above: &[LaneMask<N>; 7],
    abs: F32s<N>,
) -> (F32s<N>, F32s<N>) {
    let (a0, _) = pick(at_or_above, |j| F32s::splat(RUDDER_ALPHA_DEG[j]));
    let cl = lerp_lanes(at_or_above, a0, |j| F32s::splat(RUDDER_CL[j]), abs);
    let cd = lerp_lanes(at_or_above, a0, |j| F32s::splat(RUDDER_CD[j]), abs);
    (cl, cd)
}

impl LaneModel for Bourg {
    type Lanes = BourgLanes;
    type Shared = ();
    type Vars = BourgVars<BourgLanes>;
    type Terms = BourgTerms<BourgLanes>;
    type AircraftError = core::convert::Infallible;
    /// Bourg's step calls only `asinf`, which has no vectorised form.
    const HAS_FAST: bool = false;
    /// `3 · 1e18² < f32::MAX`: the speed of a state whose components are all
    /// below it cannot overflow `f32`.
    const SUSPECT: f32 = 1e18;

    /// A [`BourgAircraft`] is validated by its constructor.
    fn check_aircraft(_: &BourgAircraft) -> Result<(), Self::AircraftError> {
        Ok(())
    }

    fn shared(_: &BourgAircraft) {}

    fn idle(aircraft: &BourgAircraft) -> (Self::Vars, Self::Terms) {
        let one = vars(&BourgState::initial());
        let splat3 = |v: V3<f32>| V3::splat(v.x, v.y, v.z);
        let o = one.orientation;
        let vars = BourgVars {
            position_ft: splat3(one.position_ft),
            velocity_ftps: splat3(one.velocity_ftps),
            velocity_body_ftps: splat3(one.velocity_body_ftps),
            angular_velocity_radps: splat3(one.angular_velocity_radps),
            orientation: generic::Q4 {
                w: F32s::splat(o.w),
                x: F32s::splat(o.x),
                y: F32s::splat(o.y),
                z: F32s::splat(o.z),
            },
            stalling: LaneMask([false; LANES]),
        };
        let terms = BourgTerms::splat(&BourgTerms::new(aircraft, &BourgControls::initial()));
        (vars, terms)
    }

    #[inline]
    fn state(v: &Self::Vars, time_s: f64, lane: usize) -> BourgState {
        let o = &v.orientation;
        let one = BourgVars {
            position_ft: v.position_ft.lane(lane),
            velocity_ftps: v.velocity_ftps.lane(lane),
            velocity_body_ftps: v.velocity_body_ftps.lane(lane),
            angular_velocity_radps: v.angular_velocity_radps.lane(lane),
            orientation: generic::Q4 {
                w: o.w.0[lane],
                x: o.x.0[lane],
                y: o.y.0[lane],
                z: o.z.0[lane],
            },
            stalling: v.stalling.0[lane],
        };
        state_of(&one, time_s)
    }

    #[inline]
    fn set_state(v: &mut Self::Vars, lane: usize, s: &BourgState) -> f64 {
        let one = vars(s);
        v.position_ft.set_lane(lane, one.position_ft);
        v.velocity_ftps.set_lane(lane, one.velocity_ftps);
        v.velocity_body_ftps.set_lane(lane, one.velocity_body_ftps);
        v.angular_velocity_radps
            .set_lane(lane, one.angular_velocity_radps);
        let o = &mut v.orientation;
        o.w.0[lane] = one.orientation.w;
        o.x.0[lane] = one.orientation.x;
        o.y.0[lane] = one.orientation.y;
        o.z.0[lane] = one.orientation.z;
        v.stalling.0[lane] = one.stalling;
        s.time_s
    }

    fn set_controls(
        terms: &mut Self::Terms,
        lane: usize,
        aircraft: &BourgAircraft,
        (): &(),
        controls: &BourgControls,
    ) {
        terms.set_lane(lane, &BourgTerms::new(aircraft, controls));
    }

    /// [`Self::set_controls`] of each of the first `count` lanes (the
    /// provided body), always inlined into the caller (a fleet's
    /// dispatched function), rather than a call per lane.
    #[inline(always)]
    fn set_controls_lanes(
        terms: &mut Self::Terms,
        count: usize,
        aircraft: &BourgAircraft,
        (): &(),
        controls: &[BourgControls; LANES],
    ) {
        for (lane, c) in controls.iter().enumerate().take(count) {
            terms.set_lane(lane, &BourgTerms::new(aircraft, c));
        }
    }

    #[inline(always)]
    fn step_lanes<F: Maths>(
        aircraft: &BourgAircraft,
        (): &(),
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: f32,
    ) -> Self::Vars {
        generic::step::<BourgLanes, F, NoPermutes>(NoPermutes, aircraft, terms, vars, dt)
    }

    /// The look-ups' entries fetched with `permutes` where they permute
    /// (the same bits as [`Self::step_lanes`]).
    #[inline(always)]
    fn step_lanes_permuting<F: Maths, P: Permutes>(
        permutes: P,
        aircraft: &BourgAircraft,
        (): &(),
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: f32,
    ) -> Self::Vars {
        generic::step::<BourgLanes, F, P>(permutes, aircraft, terms, vars, dt)
    }

    #[inline(always)]
    fn for_each_component(v: &Self::Vars, mut f: impl FnMut(BourgLanes)) {
        for w in [
            v.position_ft,
            v.velocity_ftps,
            v.velocity_body_ftps,
            v.angular_velocity_radps,
        ] {
            f(w.x);
            f(w.y);
            f(w.z);
        }
        let o = &v.orientation;
        for q in [o.w, o.x, o.y, o.z] {
            f(q);
        }
    }

    #[inline(always)]
    fn above_ground(v: &Self::Vars) -> LaneMask<LANES> {
        v.position_ft.z.gt(0.0)
    }

    /// Feet widened to `f64` and multiplied by
    /// [`METRES_PER_FOOT`](crate::units::METRES_PER_FOOT), as `Bourg::view`.
    #[inline]
    fn position_m(state: &BourgState) -> Vector3<f64> {
        state.position_ft.map(f64::from) * crate::units::METRES_PER_FOOT
    }

    /// The provided body, written out (and not inlined) so that this
    /// model's fleet kernel is compiled once, in this crate
    /// ([`crate::real::kernel`]).
    #[cfg(feature = "std")]
    fn run_blocks(
        blocks: &mut [crate::real::kernel::Block<Self>],
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        dt: Self::TimeStep,
        arch: pulp::Arch,
        fast: bool,
        fly: bool,
    ) {
        crate::real::kernel::run_blocks::<Self>(blocks, aircraft, shared, dt, arch, fast, fly);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bourg::{airfoil_coefficients, rudder_coefficients};

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
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x8000_0001),
            f32::MAX,
            f32::MIN,
        ]);
        // Every `f32` within 300 ulps of each abscissa (airfoil and rudder,
        // both signs), where the interval and the interpolation's rounding
        // change; then the bit patterns of -25..25 at a prime stride (about
        // 140,000 values spread over every binade down to the subnormals);
        // then random bit patterns (a fixed xorshift, NaN payloads and
        // infinities included).
        for t in AIRFOIL_ALPHA_DEG.iter().chain(&RUDDER_ALPHA_DEG) {
            for x in [*t, -*t] {
                let bits = x.to_bits();
                for d in 0..=300 {
                    v.push(f32::from_bits(bits.wrapping_add(d)));
                    v.push(f32::from_bits(bits.wrapping_sub(d)));
                }
            }
        }
        for sign in [0, 0x8000_0000_u32] {
            v.extend(
                (0..=25.0_f32.to_bits())
                    .step_by(15_013)
                    .map(|b| f32::from_bits(b | sign)),
            );
        }
        let mut x = 0x2545_f491_u32;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            v.push(f32::from_bits(x));
        }
        v
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn only_evenly_spaced_abscissae_divide_by_the_step() {
        // `evenly_spaced`: each abscissa exactly `STEP_DEG` above the previous
        // one; anything else must be refused (the compile-time check that
        // lets the look-ups multiply by `INVERSE_STEP`).
        assert!(evenly_spaced(&AIRFOIL_ALPHA_DEG));
        assert!(evenly_spaced(&RUDDER_ALPHA_DEG));
        assert!(evenly_spaced(&[3.0]));
        assert!(!evenly_spaced(&[0.0, 4.0, 9.0]));
        assert!(!evenly_spaced(&[0.0, -4.0]));
        assert!(!evenly_spaced(&[0.0, 4.000_001]));
        assert!(!evenly_spaced(&[0.0, 4.0, 8.0, 11.999_999]));
        assert!(!evenly_spaced(&[f32::NAN, 4.0]));
    }

    /// The permutes as [`Permutes`] defines them, lane by lane: the permuted
    /// look-ups (their 32-entry tables, the indices into them) checked on
    /// every CPU, not only on one with AVX-512. A mutant of the tables'
    /// layout survived on an AMD EPYC without AVX-512 (2026-12-07).
    #[derive(Debug, Clone, Copy)]
    struct PortablePermutes;

    impl Permutes for PortablePermutes {
        fn permute_32<const N: usize>(
            self,
            table: &[f32; 32],
            index: [u32; N],
        ) -> Option<[f32; N]> {
            Some(core::array::from_fn(|l| table[(index[l] % 32) as usize]))
        }
    }

    #[test]
    fn table_lookups_are_the_scalar_ones() {
        // Every form: the selects, the permutes lane by lane, and the
        // instruction's permutes where this CPU has them (AVX-512).
        check_lookups(NoPermutes);
        check_lookups(PortablePermutes);
        #[cfg(target_arch = "x86_64")]
        if let Some(simd) = pulp::x86::V4::try_new() {
            check_lookups(simd);
        }
    }

    /// On a CPU with AVX-512 the fleet kernel's look-ups really are the
    /// permutes (not the selects they fall back to when an instruction set
    /// has none), and each permuted coefficient has the selected one's bits
    /// before the lanes outside the table are set, in every lane.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx512_lookups_are_permuted_with_the_selects_bits() {
        let Some(simd) = pulp::x86::V4::try_new() else {
            return;
        };
        let flaps = [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp];
        let angles = angles();
        for (c, chunk) in angles.chunks(LANES).enumerate() {
            let mut lanes = [0.0; LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let angle = F32s(lanes);
            let flap_lanes: [Flap; LANES] = core::array::from_fn(|l| flaps[(l + c) % 3]);
            let (at, _) = at_or_above(&AIRFOIL_ALPHA_DEG, angle);
            let permuted = airfoil_permuted(simd, &at, angle, flap_lanes)
                .expect("AVX-512 permutes the airfoil tables");
            let selected = airfoil_selected(&at, angle, flap_lanes);
            let abs = angle.abs();
            let (rudder_at, _) = at_or_above(&RUDDER_ALPHA_DEG, abs);
            let rudder =
                rudder_permuted(simd, &rudder_at, abs).expect("AVX-512 permutes the rudder table");
            let rudder_selected = rudder_selected(&rudder_at, abs);
            for l in 0..LANES {
                for (p, s) in [
                    (permuted.0, selected.0),
                    (permuted.1, selected.1),
                    (rudder.0, rudder_selected.0),
                    (rudder.1, rudder_selected.1),
                ] {
                    assert!(same(p.0[l], s.0[l]), "{} {:?}", lanes[l], flap_lanes[l]);
                }
            }
        }
    }

    fn check_lookups<P: Permutes>(permutes: P) {
        // Each angle in each flap's table: the lanes' flaps mixed (each
        // lane's neighbours on other tables) and shared by the whole block.
        let flaps = [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp];
        let assignments: Vec<[Flap; LANES]> = (0..3)
            .map(|r| core::array::from_fn(|l| flaps[(l + r) % 3]))
            .chain(flaps.map(|f| [f; LANES]))
            .collect();
        let angles = angles();
        for (chunk, flap_lanes) in angles
            .chunks(LANES)
            .flat_map(|c| assignments.iter().map(move |f| (c, *f)))
        {
            let mut lanes = [0.0; LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let (cl, cd) = BourgLanes::airfoil(F32s(lanes), flap_lanes, permutes);
            let (rl, rd) = BourgLanes::rudder(F32s(lanes), permutes);
            for l in 0..LANES {
                let (scl, scd) = airfoil_coefficients(lanes[l], flap_lanes[l]);
                assert!(
                    same(cl.0[l], scl) && same(cd.0[l], scd),
                    "{} ({:#x}) {:?} {permutes:?}",
                    lanes[l],
                    lanes[l].to_bits(),
                    flap_lanes[l]
                );
                let (srl, srd) = rudder_coefficients(lanes[l]);
                assert!(
                    same(rl.0[l], srl) && same(rd.0[l], srd),
                    "rudder {} {permutes:?}",
                    lanes[l]
                );
            }
        }
    }
}
