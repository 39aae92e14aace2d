//! `BatchGeodesy` against the scalar `GeodeticOrigin::model_to_geodetic` and
//! `model_to_ecef`, and the fleets' `positions_m` against `Model::view`.
//!
//! Tolerance: none. The batch performs the scalar code's arithmetic lane-wise
//! in the same order and calls the same `hypot`, `cbrt` and `atan2`, and the
//! scalar function itself for the rare cases, so every result must have the
//! scalar bits (NaN for NaN).

use fdm_core::bourg::{Bourg, Vector3};
use fdm_core::geodesy::{Geodetic, GeodeticOrigin};
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_fleet::geodesy::BatchGeodesy;
use fdm_fleet::{Fleet, LaneFleet};

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        #[allow(clippy::cast_precision_loss)] // 53 random bits, exact
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn same_geodetic(a: &Geodetic, b: &Geodetic) -> bool {
    same(a.lat_deg, b.lat_deg) && same(a.lon_deg, b.lon_deg) && same(a.alt_m, b.alt_m)
}

/// Positions within 1,000 km of the origin at -500 m to 20 km, plus the
/// special cases: the origin, far out, near the Earth's centre (its own
/// branch of the closed form), on the polar axis and the equatorial plane
/// (when the origin puts them there exactly), beyond the point-Earth distance along
/// an axis, huge and non-finite components.
fn positions(rng: &mut Rng, n: usize) -> Vec<Vector3<f64>> {
    let mut v: Vec<Vector3<f64>> = (0..n)
        .map(|_| {
            Vector3::new(
                rng.range(-1.0e6, 1.0e6),
                rng.range(-1.0e6, 1.0e6),
                rng.range(-500.0, 20_000.0),
            )
        })
        .collect();
    v.extend([
        Vector3::zeros(),
        Vector3::new(0.0, 0.0, -6.3e6),
        Vector3::new(10.0, -20.0, -6.37e6),
        // On the equatorial plane inside the evolute (`a e²`, 42.7 km from
        // the centre) when the origin is on the equator.
        Vector3::new(0.0, 25_000.0, -6.35e6),
        Vector3::new(0.0, 0.0, 4.0e7),
        Vector3::new(1e22, 0.0, 0.0),
        Vector3::new(0.0, 5e21, 1.0),
        Vector3::new(1e300, 1e300, 1e300),
        // Beyond the point-Earth distance (`2a/ε`, 5.7e22 m) along one axis
        // of the model frame: at the origins on the equator and the poles
        // the other ECEF components are small, so only the bound on every
        // component keeps these from the common lane-wise path.
        Vector3::new(1e23, 0.0, 0.0),
        Vector3::new(0.0, -6e22, 0.0),
        Vector3::new(0.0, 0.0, 1e25),
        Vector3::new(0.0, 0.0, 1e23),
        Vector3::new(1e6, 3e5, 8e22),
        // Exactly on the polar axis (ECEF x = y = 0) when the origin is at
        // latitude 0, longitude 0: straight down by `a`, then north, inside
        // the Earth and beyond the pole.
        Vector3::new(1e6, 0.0, -6_378_137.0),
        Vector3::new(7e6, 0.0, -6_378_137.0),
        // 1e-160 m off that axis, 1 km north of the centre: `p` underflows to
        // 0, so the cubic's `s` and `disc` are 0 with `r` negative, and the
        // closed form's `u` is negative (its other branch for `u + v`).
        Vector3::new(1000.0, -1e-160, -6_378_137.0),
        Vector3::new(f64::NAN, 0.0, 0.0),
        Vector3::new(0.0, f64::INFINITY, 0.0),
        Vector3::new(0.0, 0.0, f64::NEG_INFINITY),
    ]);
    v
}

#[test]
fn batches_are_the_scalar_functions_bit_for_bit() {
    let origins = [
        GeodeticOrigin::WRIGHT_PATTERSON,
        Geodetic {
            lat_deg: 0.0,
            lon_deg: 0.0,
            alt_m: 0.0,
        },
        Geodetic {
            lat_deg: 90.0,
            lon_deg: 0.0,
            alt_m: 0.0,
        },
        Geodetic {
            lat_deg: -90.0,
            lon_deg: 45.0,
            alt_m: 1000.0,
        },
        Geodetic {
            lat_deg: -33.9,
            lon_deg: 179.9,
            alt_m: -50.0,
        },
    ];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut rng = Rng(3);
    for (k, origin) in origins.into_iter().enumerate() {
        let origin = GeodeticOrigin::from_geodetic(origin).unwrap();
        let batch = BatchGeodesy::new(origin);
        // Sizes around the lane count and across several rayon tasks.
        for n in [0, 1, 7, 9, 1000, 9000] {
            let positions = positions(&mut rng, n);
            let (mut geodetic, mut par_geodetic) = (Vec::new(), Vec::new());
            let (mut ecef, mut par_ecef) = (Vec::new(), Vec::new());
            batch.geodetic_into(&positions, &mut geodetic);
            batch.ecef_into(&positions, &mut ecef);
            pool.install(|| {
                batch.par_geodetic_into(&positions, &mut par_geodetic);
                batch.par_ecef_into(&positions, &mut par_ecef);
            });
            assert_eq!(geodetic.len(), positions.len());
            assert_eq!(par_ecef.len(), positions.len());
            for (i, p) in positions.iter().enumerate() {
                let want = origin.model_to_geodetic(*p);
                assert!(
                    same_geodetic(&geodetic[i], &want) && same_geodetic(&par_geodetic[i], &want),
                    "origin {k}, {p:?}: {:?} / {:?} != {want:?}",
                    geodetic[i],
                    par_geodetic[i]
                );
                let want = origin.model_to_ecef(*p);
                for got in [ecef[i], par_ecef[i]] {
                    assert!(
                        (0..3).all(|j| same(got[j], want[j])),
                        "origin {k}, {p:?}: {got:?} != {want:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn fleet_positions_are_the_views_positions() {
    fn check<F: LaneFleet>() {
        let mut fleet = F::demonstration(37).unwrap();
        for _ in 0..5 {
            fleet.par_fly(30.0, fdm_fleet::Precision::Exact).unwrap();
        }
        let mut positions = Vec::new();
        fleet.positions_m(&mut positions);
        assert_eq!(positions.len(), 37);
        let aircraft = F::Model::default_aircraft();
        for (i, p) in positions.iter().enumerate() {
            let (controls, _) = F::Model::fleet_member(i);
            let view = F::Model::view(&aircraft, &controls, &fleet.state(i).unwrap());
            assert_eq!(*p, view.position_m, "{} #{i}", F::Model::NAME);
        }
    }
    check::<Fleet<Palmer>>();
    check::<Fleet<Bourg>>();
    // The models are the ones named.
    assert_eq!(<Fleet<Palmer> as LaneFleet>::Model::NAME, Palmer::NAME);
    assert_eq!(<Fleet<Bourg> as LaneFleet>::Model::NAME, Bourg::NAME);
}
