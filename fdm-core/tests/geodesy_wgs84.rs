//! WGS-84 geodetic <-> ECEF conversions: published test vectors, defining
//! points of the ellipsoid, round trips over the whole range of heights, the
//! degenerate cases, and no-panic properties.

use fdm_core::geodesy::{
    ecef_to_geodetic, enu_to_ecef_rotation, geodetic_to_ecef, Geodetic, WGS84_A_M, WGS84_B_M,
    WGS84_F,
};
use nalgebra::Vector3;
use proptest::prelude::*;

fn dms(deg: f64, min: f64, sec: f64) -> f64 {
    deg + min / 60.0 + sec / 3600.0
}

fn geo(lat_deg: f64, lon_deg: f64, alt_m: f64) -> Geodetic {
    Geodetic {
        lat_deg,
        lon_deg,
        alt_m,
    }
}

/// Largest ECEF distance, metres, between a point and its round trip
/// ECEF -> geodetic -> ECEF. The forward conversion is a closed form checked
/// against the EPSG vector below, so this measures the inverse's error as a
/// distance (well defined at the poles, where longitude is arbitrary).
fn ecef_round_trip_error_m(ecef: Vector3<f64>) -> f64 {
    (geodetic_to_ecef(ecef_to_geodetic(ecef)) - ecef).norm()
}

#[test]
fn constants_match_nima_tr8350_2() {
    // NIMA TR8350.2 (3rd ed., 2000), table 3.1 defining parameters and
    // table 3.3 derived semi-minor axis b = 6356752.3142 m.
    assert_eq!(WGS84_A_M, 6_378_137.0);
    assert_eq!(1.0 / WGS84_F, 298.257_223_563);
    assert!(
        (WGS84_B_M - 6_356_752.314_2).abs() < 5e-5,
        "b = {WGS84_B_M}"
    );
}

/// IOGP Publication 373-7-2 (Geomatics Guidance Note 7 part 2, "Coordinate
/// Conversions and Transformations including Formulas"), section
/// "Geographic/geocentric conversions" (EPSG method code 9602), worked example
/// on WGS 84: latitude 53°48'33.820"N, longitude 2°07'46.380"E, ellipsoidal
/// height 73.0 m <-> X = 3771793.968 m, Y = 140253.342 m, Z = 5124304.349 m.
#[test]
fn epsg_guidance_note_7_2_geocentric_example() {
    let g = geo(dms(53.0, 48.0, 33.820), dms(2.0, 7.0, 46.380), 73.0);
    let published = Vector3::new(3_771_793.968, 140_253.342, 5_124_304.349);

    let ecef = geodetic_to_ecef(g);
    // Published to the millimetre: allow half a unit of the last digit.
    for i in 0..3 {
        assert!(
            (ecef[i] - published[i]).abs() <= 0.0005,
            "axis {i}: {} vs {}",
            ecef[i],
            published[i]
        );
    }

    let back = ecef_to_geodetic(published);
    // Published to 0.001 arc-second (3 cm in latitude): half of that.
    let half_mas_deg = 0.0005 / 3600.0;
    assert!((back.lat_deg - g.lat_deg).abs() <= half_mas_deg, "{back:?}");
    assert!((back.lon_deg - g.lon_deg).abs() <= half_mas_deg, "{back:?}");
    assert!((back.alt_m - 73.0).abs() <= 0.0005, "{back:?}");
}

#[test]
fn defining_points_of_the_ellipsoid() {
    let a = WGS84_A_M;
    let b = WGS84_B_M;
    // (geodetic, ECEF) pairs that follow from the definition of the axes.
    let cases = [
        (geo(0.0, 0.0, 0.0), Vector3::new(a, 0.0, 0.0)),
        (geo(0.0, 90.0, 0.0), Vector3::new(0.0, a, 0.0)),
        (geo(0.0, -90.0, 0.0), Vector3::new(0.0, -a, 0.0)),
        (geo(0.0, 180.0, 1000.0), Vector3::new(-a - 1000.0, 0.0, 0.0)),
        (geo(90.0, 0.0, 0.0), Vector3::new(0.0, 0.0, b)),
        (geo(-90.0, 0.0, 500.0), Vector3::new(0.0, 0.0, -b - 500.0)),
    ];
    for (g, ecef) in cases {
        let fwd = geodetic_to_ecef(g);
        assert!((fwd - ecef).norm() < 1e-8, "{g:?} -> {fwd} vs {ecef}");
        let back = ecef_to_geodetic(ecef);
        assert!(
            (back.lat_deg - g.lat_deg).abs() < 1e-12,
            "{ecef} -> {back:?}"
        );
        assert!((back.alt_m - g.alt_m).abs() < 1e-8, "{ecef} -> {back:?}");
        if g.lat_deg.abs() < 90.0 {
            // ±180 are the same meridian; compare as angles.
            let dlon = (back.lon_deg - g.lon_deg + 540.0).rem_euclid(360.0) - 180.0;
            assert!(dlon.abs() < 1e-12, "{ecef} -> {back:?}");
        } else {
            // On the polar axis the longitude is reported as 0.
            assert_eq!(back.lon_deg, 0.0);
        }
    }
}

#[test]
fn round_trip_over_all_latitudes_and_heights() {
    // From deep inside the Earth to far beyond geostationary orbit.
    let heights_m = [
        -6.0e6, -1.0e6, -1.0e4, -100.0, 0.0, 251.0, 1.0e4, 1.0e5, 1.0e6, 3.6e7, 1.0e9,
    ];
    let mut worst_m = 0.0_f64;
    let mut worst_rel = 0.0_f64;
    for &h in &heights_m {
        for i in 0..=360 {
            let lat = -90.0 + 0.5 * f64::from(i);
            for &lon in &[-180.0, -84.0483, 0.0, 33.3, 135.0] {
                let ecef = geodetic_to_ecef(geo(lat, lon, h));
                let err = ecef_round_trip_error_m(ecef);
                worst_m = worst_m.max(err);
                // Relative to the size of the numbers involved (at least a).
                worst_rel = worst_rel.max(err / ecef.norm().max(WGS84_A_M));
                let back = ecef_to_geodetic(ecef);
                // Heights and latitudes come back too (not only the point).
                assert!(
                    (back.alt_m - h).abs() <= 1e-8 + 1e-15 * h.abs(),
                    "{back:?} vs h {h}"
                );
                assert!((back.lat_deg - lat).abs() < 1e-12, "{back:?} vs lat {lat}");
            }
        }
    }
    // Measured (0.05° grid): at most 4.1e-9 m for heights from -6000 km to
    // +1000 km, 2.0e-8 m at 36 000 km, 4.5e-7 m at 1e9 m: relative to
    // max(|r|, a) at most 6.4e-16, i.e. a few ulps. Latitude within 5e-14°.
    assert!(worst_rel < 2e-15, "worst relative error {worst_rel:e}");
    assert!(worst_m < 2e-6, "worst error {worst_m:e} m");
    eprintln!("worst round-trip error {worst_m:e} m, relative {worst_rel:e}");
}

#[test]
fn near_the_surface_the_round_trip_is_nanometres() {
    let mut worst = 0.0_f64;
    for i in 0..=1800 {
        let lat = -90.0 + 0.1 * f64::from(i);
        for &h in &[-500.0, 0.0, 251.0, 12_000.0, 100_000.0] {
            worst = worst.max(ecef_round_trip_error_m(geodetic_to_ecef(geo(lat, 17.0, h))));
        }
    }
    assert!(worst < 1e-8, "worst {worst:e} m");
}

#[test]
fn centre_and_equatorial_plane_inside_the_evolute() {
    // The Earth's centre: GeographicLib's convention, north pole at depth b.
    let c = ecef_to_geodetic(Vector3::zeros());
    assert_eq!(c.lat_deg, 90.0);
    assert!((c.alt_m + WGS84_B_M).abs() < 1e-6, "{c:?}");

    // Points on the equatorial plane closer to the axis than a·e² (42.7 km)
    // have their nearest ellipsoid point off the equator; the height is then
    // -N(1 - e²) and the result must map back to the same point.
    let e2 = WGS84_F * (2.0 - WGS84_F);
    for i in 0..=20 {
        let x = WGS84_A_M * e2 * f64::from(i) / 21.0;
        for sign in [1.0, -1.0] {
            let p = Vector3::new(x * sign, 0.0, 0.0);
            let g = ecef_to_geodetic(p);
            assert!(g.lat_deg.is_finite() && g.alt_m.is_finite(), "{p} -> {g:?}");
            assert!(ecef_round_trip_error_m(p) < 1e-6, "{p} -> {g:?}");
        }
        // Tiny negative z picks the southern solution: the mirror image of
        // the northern one (the ellipsoid is symmetric about the equator),
        // and it maps back to the same point too.
        let south = Vector3::new(x, 0.0, -1e-300);
        let g = ecef_to_geodetic(south);
        assert!(g.lat_deg <= 0.0, "{g:?}");
        let north = ecef_to_geodetic(Vector3::new(x, 0.0, 0.0));
        assert_eq!(g.lat_deg, -north.lat_deg, "{g:?} {north:?}");
        assert_eq!(g.alt_m, north.alt_m, "{g:?} {north:?}");
        assert!(ecef_round_trip_error_m(south) < 1e-6, "{g:?}");
    }
}

/// The closed form holds out to `2a/ε` (5.7e22 m, GeographicLib's bound):
/// on the equator and the polar axis the height is the distance less `a` or
/// `b`, within an ulp of the distance (the ulp is 4 to 8 million metres
/// there, so the radius still shows). Beyond it the Earth is a point (the
/// function's doc): the height is the distance and latitude and longitude
/// are the direction from the centre, out to 1.7e308 m without overflow.
#[test]
fn far_space_up_to_and_beyond_the_point_earth_bound() {
    let bound = 2.0 * WGS84_A_M / f64::EPSILON;
    let ulp = |x: f64| f64::from_bits(x.to_bits() + 1) - x;
    for d in [3e22, 4e22, bound] {
        let equator = ecef_to_geodetic(Vector3::new(d, 0.0, 0.0));
        let pole = ecef_to_geodetic(Vector3::new(0.0, 0.0, -d));
        for (g, radius) in [(equator, WGS84_A_M), (pole, WGS84_B_M)] {
            assert!(
                g.alt_m < d && (g.alt_m - (d - radius)).abs() <= ulp(d),
                "{d:e}: {g:?}"
            );
        }
        assert_eq!((equator.lat_deg, pole.lat_deg), (0.0, -90.0));
    }
    let past = f64::from_bits(bound.to_bits() + 1);
    for d in [past, 1e23, 1e100, 1e300, 1e308, 1.7e308] {
        for (lat_deg, lon_deg) in [(35.0, 20.0), (-60.0, 135.0), (10.0, -100.0), (-5.0, -170.0)] {
            let (sin_lat, cos_lat) = f64::to_radians(lat_deg).sin_cos();
            let (sin_lon, cos_lon) = f64::to_radians(lon_deg).sin_cos();
            let p = Vector3::new(d * cos_lat * cos_lon, d * cos_lat * sin_lon, d * sin_lat);
            let g = ecef_to_geodetic(p);
            assert!((g.lat_deg - lat_deg).abs() < 1e-12, "{p} -> {g:?}");
            assert!((g.lon_deg - lon_deg).abs() < 1e-12, "{p} -> {g:?}");
            assert!((g.alt_m - d).abs() <= 2.0 * ulp(d), "{p} -> {g:?}");
        }
    }
}

/// Within `a·e²` (42.7 km) of the centre, off the equatorial plane, the
/// quartic's cubic resolvent has a negative `r` and, near the axis, three real
/// roots; the root is taken free of cancellation there too, so these points
/// round trip as closely as any other.
#[test]
fn near_the_centre_off_the_equatorial_plane() {
    let e2 = WGS84_F * (2.0 - WGS84_F);
    let mut worst = 0.0_f64;
    for i in -8..=8 {
        let x = WGS84_A_M * e2 * f64::from(i) / 8.0;
        for j in 1..=8 {
            for z in [
                f64::from(j) * 5_000.0,
                1e-3 * f64::from(j),
                -f64::from(j) * 4_000.0,
            ] {
                for p in [Vector3::new(x, 0.0, z), Vector3::new(0.6 * x, 0.8 * x, z)] {
                    let g = ecef_to_geodetic(p);
                    assert!(g.lat_deg.is_finite() && g.alt_m.is_finite(), "{p} -> {g:?}");
                    assert_eq!(g.lat_deg > 0.0, z > 0.0, "{p} -> {g:?}");
                    let err = ecef_round_trip_error_m(p);
                    worst = worst.max(err);
                }
            }
        }
    }
    assert!(worst < 1e-8, "worst {worst:e} m");
}

#[test]
fn non_finite_input_gives_nan() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for axis in 0..3 {
            let mut p = Vector3::new(4.0e6, 1.0e6, 4.0e6);
            p[axis] = bad;
            let g = ecef_to_geodetic(p);
            assert!(
                g.lat_deg.is_nan() && g.lon_deg.is_nan() && g.alt_m.is_nan(),
                "{p} -> {g:?}"
            );
        }
    }
    let e = geodetic_to_ecef(geo(f64::NAN, 0.0, 0.0));
    assert!(e.iter().all(|c| c.is_nan()), "{e}");
}

#[test]
fn enu_rotation_is_orthonormal_and_points_the_right_way() {
    for &(lat, lon) in &[
        (0.0, 0.0),
        (39.8264, -84.0483),
        (-33.9, 151.2),
        (90.0, 10.0),
    ] {
        let r = enu_to_ecef_rotation(lat, lon);
        assert!((r.transpose() * r - nalgebra::Matrix3::identity()).norm() < 1e-15);
        assert!((r.determinant() - 1.0).abs() < 1e-15);
    }
    // At lat 0, lon 0: east = +y, north = +z, up = +x (ECEF).
    let r = enu_to_ecef_rotation(0.0, 0.0);
    assert_eq!(r.column(0), Vector3::new(0.0, 1.0, 0.0));
    assert_eq!(r.column(1), Vector3::new(0.0, 0.0, 1.0));
    assert_eq!(r.column(2), Vector3::new(1.0, 0.0, 0.0));
    // Up is the ellipsoid normal: a small step up changes only the height.
    let base = geo(39.8264, -84.0483, 251.0);
    let up = enu_to_ecef_rotation(base.lat_deg, base.lon_deg)
        .column(2)
        .into_owned();
    let g = ecef_to_geodetic(geodetic_to_ecef(base) + up * 10.0);
    assert!(
        (g.alt_m - 261.0).abs() < 1e-8 && (g.lat_deg - base.lat_deg).abs() < 1e-13,
        "{g:?}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Any finite ECEF point out to 1e10 m maps to a valid geodetic position
    /// that maps back to the same point.
    #[test]
    fn finite_ecef_round_trips(
        x in -1.0e10..1.0e10_f64,
        y in -1.0e10..1.0e10_f64,
        z in -1.0e10..1.0e10_f64,
        scale_exp in -10..0_i32,
    ) {
        // Mix of far points and points near or inside the Earth.
        let scale = if scale_exp < -3 { 10f64.powi(scale_exp + 4) } else { 1.0 };
        let p = Vector3::new(x, y, z) * scale;
        let g = ecef_to_geodetic(p);
        prop_assert!(g.lat_deg.is_finite() && g.lon_deg.is_finite() && g.alt_m.is_finite());
        prop_assert!((-90.0..=90.0).contains(&g.lat_deg));
        prop_assert!((-180.0..=180.0).contains(&g.lon_deg));
        let err = ecef_round_trip_error_m(p);
        prop_assert!(err <= 1e-8 + 2e-15 * p.norm(), "{} -> {:?}: {:e} m", p, g, err);
    }

    /// No input, however extreme, panics; finite input never gives NaN.
    #[test]
    fn never_panics(x in any::<f64>(), y in any::<f64>(), z in any::<f64>()) {
        let g = ecef_to_geodetic(Vector3::new(x, y, z));
        if x.is_finite() && y.is_finite() && z.is_finite() {
            prop_assert!(!g.lat_deg.is_nan() && !g.lon_deg.is_nan() && !g.alt_m.is_nan(), "{:?}", g);
        }
        let _ = geodetic_to_ecef(Geodetic { lat_deg: x, lon_deg: y, alt_m: z });
    }
}
