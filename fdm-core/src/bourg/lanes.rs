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
//! In lanes the search is a branchless count of the table entries `<=` the
//! angle, over the three flap settings' tables of a coefficient laid end to
//! end (a lane's table is an offset, its two entries a gather), and the
//! interpolation is the scalar formula, lane-wise. The unit test below
//! compares both with the scalar functions bit for bit.
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

use crate::real::{F32s, LaneMask, LaneModel, Maths, Real, V3};

/// Aircraft per block of a Bourg fleet: 16 `f32` lanes (one AVX-512 register,
/// two AVX2 ones).
pub const LANES: usize = 16;

/// The lane vector of a Bourg fleet.
pub type BourgLanes = F32s<LANES>;

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
fn interval_lanes<const T: usize, const N: usize>(
    a: &[f32; T],
    angle: F32s<N>,
) -> ([u32; N], LaneMask<N>) {
    let mut count = [0_u32; N];
    for &entry in a {
        for (c, &x) in count.iter_mut().zip(&angle.0) {
            *c += u32::from(entry <= x);
        }
    }
    let valid = LaneMask(core::array::from_fn(|l| {
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
fn lerp_lanes<const T: usize, const N: usize>(
    a: &[f32; T],
    tables: &[f32],
    offset: &[u32; N],
    index: &[u32; N],
    angle: F32s<N>,
) -> F32s<N> {
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

impl<const N: usize> BourgReal for F32s<N> {
    /// Each lane's offset in the tables laid end to end (`table_offset`).
    type Table = [u32; N];

    #[inline(always)]
    fn table(flap: Flap) -> [u32; N] {
        [table_offset(flap); N]
    }

    #[inline(always)]
    fn set_table_lane(table: &mut [u32; N], i: usize, flap: Flap) {
        table[i] = table_offset(flap);
    }

    #[inline(always)]
    fn airfoil(angle: Self, offset: [u32; N]) -> (Self, Self) {
        let a = &AIRFOIL_ALPHA_DEG;
        let (index, valid) = interval_lanes(a, angle);
        let cl = lerp_lanes(a, &CL_TABLES, &offset, &index, angle);
        let cd = lerp_lanes(a, &CD_TABLES, &offset, &index, angle);
        (
            Self::select(valid, cl, Self::splat(0.0)),
            Self::select(valid, cd, Self::splat(CD_OUTSIDE)),
        )
    }

    #[inline(always)]
    fn rudder(angle: Self) -> (Self, Self) {
        let a = &RUDDER_ALPHA_DEG;
        let abs = angle.abs();
        let (index, valid) = interval_lanes(a, abs);
        let zero = [0; N];
        let cl = lerp_lanes(a, &RUDDER_CL, &zero, &index, abs);
        let cl = Self::select(angle.lt(0.0), -cl, cl);
        let cd = lerp_lanes(a, &RUDDER_CD, &zero, &index, abs);
        (
            Self::select(valid, cl, Self::splat(0.0)),
            Self::select(valid, cd, Self::splat(CD_OUTSIDE)),
        )
    }
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

    #[inline(always)]
    fn step_lanes<F: Maths>(
        aircraft: &BourgAircraft,
        (): &(),
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: f32,
    ) -> Self::Vars {
        generic::step::<BourgLanes, F>(aircraft, terms, vars, dt)
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
        ]);
        v
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn an_entry_past_the_table_is_its_last() {
        // `entry`: "`table[i]`, `i` clamped to the table". The look-ups never
        // index past their tables, but a lane's table offset is a public
        // number (`BourgTerms::tables`, `BourgReal::airfoil`), and one that
        // is not one of the three tables' must still read inside them, not
        // panic in a fleet's kernel.
        let t = [1.0, 2.0, 3.0];
        assert_eq!(entry(&t, 0).to_bits(), 1.0_f32.to_bits());
        assert_eq!(entry(&t, 2).to_bits(), 3.0_f32.to_bits());
        for i in [3, 4, 1000, u32::MAX] {
            assert_eq!(entry(&t, i).to_bits(), 3.0_f32.to_bits(), "{i}");
        }
        // Through the hook: an offset past the tables reads their last
        // entries (finite numbers) in that lane; the others are unchanged.
        let angle = F32s([5.0_f32; LANES]);
        let mut offsets = [table_offset(Flap::Neutral); LANES];
        offsets[3] = 1000;
        let (cl, cd) = BourgLanes::airfoil(angle, offsets);
        let (scl, scd) = airfoil_coefficients(5.0, Flap::Neutral);
        for l in 0..LANES {
            if l == 3 {
                assert!(cl.0[l].is_finite() && cd.0[l].is_finite());
            } else {
                assert!(same(cl.0[l], scl) && same(cd.0[l], scd), "lane {l}");
            }
        }
    }

    #[test]
    fn table_lookups_are_the_scalar_ones() {
        let flaps = [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp];
        for chunk in angles().chunks(LANES) {
            let mut lanes = [0.0; LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let flap_lanes: [Flap; LANES] = core::array::from_fn(|l| flaps[l % 3]);
            let (cl, cd) = BourgLanes::airfoil(F32s(lanes), flap_lanes.map(table_offset));
            let (rl, rd) = BourgLanes::rudder(F32s(lanes));
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
