//! Batched geodesy: the model-frame positions of many aircraft (metres, x
//! north, y west, z up) to WGS-84 geodetic coordinates or ECEF, several
//! aircraft per SIMD instruction, for outputs that place a whole fleet on the
//! Earth every frame (FlightGear multiplayer, DIS).
//!
//! Every result is bit-identical to the scalar
//! [`GeodeticOrigin::model_to_geodetic`] / [`GeodeticOrigin::model_to_ecef`]:
//! the origin's rotation and ECEF position are read once per batch, and every
//! addition, multiplication, division and square root of the scalar code
//! (the tangent plane to ECEF, then Vermeille's closed form in
//! [`ecef_to_geodetic`]) runs lane-wise with the same operands in the same
//! order (correctly rounded in SIMD as in scalar code, never fused; see
//! [`crate::fleet`]). What still goes lane by lane, through the same
//! `fdm_core::math` functions the scalar code calls (glibc with `std`), is
//! the transcendental part: `hypot` (three calls per aircraft), `cbrt` (one)
//! and `atan2` (two). The scalar code's rare branches (a point on the polar
//! axis, on the equatorial plane inside the evolute, near the Earth's
//! centre, beyond 1e21 m, or not finite) are found by a lane mask and those
//! aircraft get the scalar function itself.
//!
//! The one `hypot` the scalar code uses only to detect points beyond about
//! 5.7e22 m (where it treats the Earth as a point) is replaced by a lane-wise
//! bound: a point with every ECEF component below 1e21 m in magnitude is
//! closer than that; any other goes to the scalar function.

use fdm_core::geodesy::{ecef_to_geodetic, Geodetic, GeodeticOrigin, WGS84_A_M, WGS84_F};
use fdm_core::math::{atan2, cbrt, hypot};
use nalgebra::Vector3;
use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

use fdm_core::real::{F64s, LaneMask as Mask, Mask as _, Real};

/// Aircraft per lane vector: 8 f64 (one AVX-512 register).
const N: usize = 8;
type L = F64s<N>;

/// Aircraft per rayon task in the `par_` methods.
const PER_TASK: usize = 4096;

/// What an output slot holds before it is written.
const UNSET: Geodetic = Geodetic {
    lat_deg: f64::NAN,
    lon_deg: f64::NAN,
    alt_m: f64::NAN,
};

/// `e² = f (2 - f)`, as `fdm_core`'s WGS-84 module defines it.
const E2: f64 = WGS84_F * (2.0 - WGS84_F);
/// `(1 - f)²`.
const E2M: f64 = (1.0 - WGS84_F) * (1.0 - WGS84_F);
/// `e⁴`.
const E4: f64 = E2 * E2;
/// Below this magnitude in every ECEF component a point is nearer than the
/// scalar code's "the Earth is a point" distance (`2a/ε`, about 5.7e22 m).
const NEAR_M: f64 = 1e21;

/// The model frame of one [`GeodeticOrigin`] placed on WGS-84, for batches of
/// positions. See the [module documentation](self).
///
/// ```
/// use fdm_core::geodesy::GeodeticOrigin;
/// use fdm_fleet::geodesy::BatchGeodesy;
/// use nalgebra::Vector3;
///
/// let origin = GeodeticOrigin::from_geodetic(GeodeticOrigin::WRIGHT_PATTERSON).unwrap();
/// let batch = BatchGeodesy::new(origin);
/// let positions: Vec<_> = (0..20).map(|i| Vector3::new(100.0 * f64::from(i), -50.0, 300.0)).collect();
/// let mut geodetic = Vec::new();
/// batch.geodetic_into(&positions, &mut geodetic);
/// for (p, g) in positions.iter().zip(&geodetic) {
///     assert_eq!(*g, origin.model_to_geodetic(*p)); // bit for bit
/// }
/// ```
#[derive(Debug, Clone, Copy)]
pub struct BatchGeodesy {
    origin: GeodeticOrigin,
    /// The origin's ECEF position.
    ecef0: [f64; 3],
    /// The ENU-to-ECEF rotation, row by row.
    rotation: [[f64; 3]; 3],
    arch: Arch,
}

impl BatchGeodesy {
    /// Batches for `origin`. Detects the CPU's instruction set once.
    #[must_use]
    pub fn new(origin: GeodeticOrigin) -> Self {
        let e = origin.ecef_m();
        let m = origin.enu_to_ecef();
        Self {
            origin,
            ecef0: [e.x, e.y, e.z],
            rotation: core::array::from_fn(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]),
            arch: Arch::new(),
        }
    }

    /// The origin.
    #[must_use]
    pub const fn origin(&self) -> &GeodeticOrigin {
        &self.origin
    }

    /// `out` becomes [`GeodeticOrigin::model_to_geodetic`] of every position,
    /// in order, on this thread.
    pub fn geodetic_into(&self, positions_m: &[Vector3<f64>], out: &mut Vec<Geodetic>) {
        out.clear();
        out.resize(positions_m.len(), UNSET);
        self.arch.dispatch(Batch {
            geodesy: self,
            positions: positions_m,
            out: Out::Geodetic(out),
        });
    }

    /// [`BatchGeodesy::geodetic_into`] on the threads of the current rayon
    /// pool; the same bits.
    pub fn par_geodetic_into(&self, positions_m: &[Vector3<f64>], out: &mut Vec<Geodetic>) {
        out.clear();
        out.resize(positions_m.len(), UNSET);
        positions_m
            .par_chunks(PER_TASK)
            .zip(out.par_chunks_mut(PER_TASK))
            .for_each(|(positions, out)| {
                self.arch.dispatch(Batch {
                    geodesy: self,
                    positions,
                    out: Out::Geodetic(out),
                });
            });
    }

    /// `out` becomes [`GeodeticOrigin::model_to_ecef`] of every position, in
    /// order, on this thread.
    pub fn ecef_into(&self, positions_m: &[Vector3<f64>], out: &mut Vec<Vector3<f64>>) {
        out.clear();
        out.resize(positions_m.len(), Vector3::zeros());
        self.arch.dispatch(Batch {
            geodesy: self,
            positions: positions_m,
            out: Out::Ecef(out),
        });
    }

    /// [`BatchGeodesy::ecef_into`] on the threads of the current rayon pool;
    /// the same bits.
    pub fn par_ecef_into(&self, positions_m: &[Vector3<f64>], out: &mut Vec<Vector3<f64>>) {
        out.clear();
        out.resize(positions_m.len(), Vector3::zeros());
        positions_m
            .par_chunks(PER_TASK)
            .zip(out.par_chunks_mut(PER_TASK))
            .for_each(|(positions, out)| {
                self.arch.dispatch(Batch {
                    geodesy: self,
                    positions,
                    out: Out::Ecef(out),
                });
            });
    }

    /// `model_to_ecef` lane-wise: `ecef0 + R · (-y, x, z)`, each row summed
    /// left to right as nalgebra's 3×3 product does.
    #[inline(always)]
    fn ecef(&self, x: L, y: L, z: L) -> [L; 3] {
        let east = -y;
        core::array::from_fn(|i| {
            let r = &self.rotation[i];
            self.ecef0[i] + (r[0] * east + r[1] * x + r[2] * z)
        })
    }

    /// `ecef_to_geodetic` lane-wise for the lanes of the common case; the
    /// others are computed by the scalar function.
    #[inline(always)]
    fn geodetic(ecef: [L; 3]) -> [Geodetic; N] {
        let [x, y, z] = ecef;
        let near: Mask<N> = Mask(core::array::from_fn(|l| {
            x.0[l].abs() < NEAR_M && y.0[l].abs() < NEAR_M && z.0[l].abs() < NEAR_M
        }));
        let r_axis = F64s(core::array::from_fn(|l| hypot(x.0[l], y.0[l])));
        let off_axis = Mask(core::array::from_fn(|l| r_axis.0[l] != 0.0));
        let sin_lon = y / r_axis;
        let cos_lon = x / r_axis;
        let p = r_axis / WGS84_A_M;
        let p = p * p;
        let zq = z / WGS84_A_M;
        let q = E2M * (zq * zq);
        let r = (p + q - E4) / 6.0;
        let general = Mask(core::array::from_fn(|l| {
            !(E4 * q.0[l] == 0.0 && r.0[l] <= 0.0)
        }));
        let s = E4 * p * q / 4.0;
        let r2 = r * r;
        let r3 = r * r2;
        let disc = s * (2.0 * r3 + s);
        let one_root = Mask(core::array::from_fn(|l| disc.0[l] >= 0.0));
        let t3 = s + r3;
        let root = disc.sqrt();
        let t3 = t3 + t3.lt(0.0).select(-root, root);
        let t = t3.map(cbrt);
        let u = r + (t + t.eq(0.0).select(L::splat(0.0), r2 / t));
        let v = (u * u + E4 * q).sqrt();
        let uv = u.lt(0.0).select(E4 * q / (v - u), u + v);
        let w = (E2 * (uv - q) / (2.0 * v)).map(|w| w.max(0.0));
        let k = uv / ((uv + w * w).sqrt() + w);
        let k1 = k;
        let k2 = k + E2;
        let d = k1 * r_axis / k2;
        let z_k1 = z / k1;
        let r_k2 = r_axis / k2;
        let hh = F64s(core::array::from_fn(|l| hypot(z_k1.0[l], r_k2.0[l])));
        let sin_lat = z_k1 / hh;
        let cos_lat = r_k2 / hh;
        let dz = F64s(core::array::from_fn(|l| hypot(d.0[l], z.0[l])));
        let h = (1.0 - E2M / k1) * dz;
        let common = near.and(off_axis).and(general).and(one_root);
        core::array::from_fn(|l| {
            if common.0[l] {
                Geodetic {
                    lat_deg: atan2(sin_lat.0[l], cos_lat.0[l]).to_degrees(),
                    lon_deg: atan2(sin_lon.0[l], cos_lon.0[l]).to_degrees(),
                    alt_m: h.0[l],
                }
            } else {
                ecef_to_geodetic(Vector3::new(x.0[l], y.0[l], z.0[l]))
            }
        })
    }
}

/// Where a batch writes.
enum Out<'a> {
    Geodetic(&'a mut [Geodetic]),
    Ecef(&'a mut [Vector3<f64>]),
}

/// One batch, generic over the instruction set pulp picked.
struct Batch<'a> {
    geodesy: &'a BatchGeodesy,
    positions: &'a [Vector3<f64>],
    out: Out<'a>,
}

impl WithSimd for Batch<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(mut self, _simd: S) {
        let g = self.geodesy;
        for (c, chunk) in self.positions.chunks(N).enumerate() {
            // The last chunk is padded with the origin (its lanes are not
            // written out).
            let lane = |f: fn(&Vector3<f64>) -> f64| {
                F64s(core::array::from_fn(|l| chunk.get(l).map_or(0.0, f)))
            };
            let ecef = g.ecef(lane(|p| p.x), lane(|p| p.y), lane(|p| p.z));
            let start = c * N;
            match &mut self.out {
                Out::Geodetic(out) => {
                    let geodetic = BatchGeodesy::geodetic(ecef);
                    for (o, g) in out[start..].iter_mut().zip(&geodetic[..chunk.len()]) {
                        *o = *g;
                    }
                }
                Out::Ecef(out) => {
                    for (l, o) in out[start..].iter_mut().take(chunk.len()).enumerate() {
                        *o = Vector3::new(ecef[0].0[l], ecef[1].0[l], ecef[2].0[l]);
                    }
                }
            }
        }
    }
}
