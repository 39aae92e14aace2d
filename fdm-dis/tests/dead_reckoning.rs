//! The sender-side dead-reckoning rule on trajectories whose truth is known
//! in closed form, so that every expected send time is derived, not
//! measured.
//!
//! * Straight flight: due east along the equator at constant height. In ECEF
//!   that is a circle of radius `R = a + h` about the z axis:
//!   `P(t) = R (cos ωt, sin ωt, 0)`, ω = v/R, heading 90°, level, body
//!   angular velocity `(0, -ω, 0)` (the nose follows the curvature: ECEF +z,
//!   north, is the body's -y when heading east), acceleration `v²/R` down.
//!   A DRM(F,P,W) receiver's error after Δ is `R·|(cos x − 1, sin x − x)|`
//!   with x = ωΔ, about `v²Δ²/(2R)`: 0.49 m for v = 250 m/s, Δ = 5 s; the
//!   orientation drifts by ωΔ = 0.011°. Both stay under 1 m / 3°, so only
//!   heartbeats go out.
//! * Turn: a steady level turn at speed v, rate Ω in the tangent plane of an
//!   origin (built in ECEF from that plane, so every input is consistent).
//!   - DRM(F,P,W): the held orientation is off by exactly ΩΔ (a rotation
//!     about the vertical), so it triggers at ΩΔ > 3°, while the position
//!     error `r·|(sin x − x, 1 − cos x)|` (r = v/Ω, x = ΩΔ) is still below
//!     1 m there (checked in the test).
//!   - DRM(R,V,W): the body rates are constant in a steady turn, so the
//!     orientation is extrapolated exactly; the position error is
//!     `r·|(sin x − x, 1 − cos x − x²/2)|`, solved here for 1 m.
//!
//! Tolerance on send times: one frame (the check runs once per frame, so a
//! send happens on the first frame past the analytic time), plus 1e-6 s for
//! the f32 rounding of the sent rates.

use fdm_dis::geodesy::{ecef_to_geodetic, geodetic_to_ecef, Attitude, Geodetic, WGS84_A_M};
use fdm_dis::{
    ned_to_ecef_rotation, AircraftKind, AircraftState, DeadReckoner, DisOutputError, DrAlgorithm,
    DrThresholds, EntityConfig, EntityIdentity, EntityPublisher, Marking, SendReason,
};
use nalgebra::Vector3;

/// 64 frames per second: exact in binary, so frame times are exact.
const DT: f64 = 1.0 / 64.0;

/// Equator, heading east, height h, speed v, at time t.
fn equator_state(t: f64, v: f64, h: f64) -> AircraftState {
    let r = WGS84_A_M + h;
    let w = v / r;
    let mut s = AircraftState::new(
        t,
        Geodetic {
            lat_deg: 0.0,
            lon_deg: (w * t).to_degrees(),
            alt_m: h,
        },
        Attitude {
            heading_deg: 90.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
        },
        Vector3::new(0.0, v, 0.0),
    );
    s.angular_velocity_body_rad_s = Some(Vector3::new(0.0, -w, 0.0));
    s.acceleration_ned_m_s2 = Some(Vector3::new(0.0, 0.0, v * v / r));
    s
}

struct Turn {
    origin: Geodetic,
    speed: f64,
    rate: f64, // rad/s, positive = right turn
    bank_deg: f64,
}

impl Turn {
    /// A coordinated level turn: rate = g tan(bank) / v.
    fn coordinated(speed: f64, bank_deg: f64) -> Self {
        Self {
            origin: Geodetic {
                lat_deg: 39.8264,
                lon_deg: -84.0483,
                alt_m: 1500.0,
            },
            speed,
            rate: 9.806_65 * bank_deg.to_radians().tan() / speed,
            bank_deg,
        }
    }

    fn radius(&self) -> f64 {
        self.speed / self.rate
    }

    /// The exact state at t, built in ECEF from the origin's tangent plane.
    fn state(&self, t: f64) -> AircraftState {
        let (v, w, r) = (self.speed, self.rate, self.radius());
        let psi = w * t; // heading in the origin's NED, starting north
                         // Circle starting at the origin heading north, turning right.
        let p_ned = Vector3::new(r * psi.sin(), r * (1.0 - psi.cos()), 0.0);
        let v_ned = Vector3::new(v * psi.cos(), v * psi.sin(), 0.0);
        let a_ned = Vector3::new(-v * w * psi.sin(), v * w * psi.cos(), 0.0);
        let c_n0_b = Attitude {
            heading_deg: psi.to_degrees(),
            pitch_deg: 0.0,
            roll_deg: self.bank_deg,
        }
        .body_to_ned();
        let c_e_n0 = ned_to_ecef_rotation(self.origin.lat_deg, self.origin.lon_deg);
        let p_ecef = geodetic_to_ecef(self.origin) + c_e_n0 * p_ned;
        let here = ecef_to_geodetic(p_ecef);
        let c_n_e = ned_to_ecef_rotation(here.lat_deg, here.lon_deg).transpose();
        let mut s = AircraftState::new(
            t,
            here,
            Attitude::from_body_to_ned(&(c_n_e * c_e_n0 * c_n0_b)),
            c_n_e * c_e_n0 * v_ned,
        );
        // Turning about the origin's down axis at rate w, in body axes.
        s.angular_velocity_body_rad_s = Some(c_n0_b.transpose() * Vector3::new(0.0, 0.0, w));
        s.acceleration_ned_m_s2 = Some(c_n_e * c_e_n0 * a_ned);
        s
    }
}

fn publisher(algorithm: DrAlgorithm, thresholds: DrThresholds) -> EntityPublisher {
    let mut config = EntityConfig::new(
        EntityIdentity::new(1, 1, 1).unwrap(),
        AircraftKind::CESSNA_172_SKYHAWK,
        Marking::new("N172SP").unwrap(),
    );
    config.dr_algorithm = algorithm;
    EntityPublisher::new(config, thresholds).unwrap()
}

/// Runs `frames` frames; returns (time, reason) of every send.
fn run(
    p: &mut EntityPublisher,
    frames: u32,
    state: impl Fn(f64) -> AircraftState,
) -> Vec<(f64, SendReason)> {
    let mut sends = Vec::new();
    for k in 0..=frames {
        let t = f64::from(k) * DT;
        if let Some(due) = p.update(&state(t)).unwrap() {
            assert_eq!(due.bytes.len(), 144);
            sends.push((t, due.reason));
        }
    }
    sends
}

#[test]
fn straight_flight_sends_only_heartbeats() {
    let duration_s = 60.0;
    let frames = (duration_s / DT) as u32;
    for algorithm in [
        DrAlgorithm::Fpw,
        DrAlgorithm::Rpw,
        DrAlgorithm::Rvw,
        DrAlgorithm::Fvw,
    ] {
        let mut p = publisher(algorithm, DrThresholds::default());
        let sends = run(&mut p, frames, |t| equator_state(t, 250.0, 3000.0));
        // First PDU at t = 0, then one every 5 s (exact frame times).
        let expected: Vec<f64> = (0..=12).map(|i| f64::from(i) * 5.0).collect();
        let times: Vec<f64> = sends.iter().map(|s| s.0).collect();
        assert_eq!(times, expected, "{algorithm:?}");
        assert_eq!(sends[0].1, SendReason::First);
        assert!(
            sends[1..].iter().all(|s| s.1 == SendReason::Heartbeat),
            "{algorithm:?}: {sends:?}"
        );
        let c = p.counts();
        assert_eq!(
            (c.frames, c.sent, c.heartbeat),
            (u64::from(frames) + 1, 13, 12)
        );
        println!(
            "{algorithm:?}: straight 60 s at 250 m/s: {} PDUs, all heartbeats",
            c.sent
        );
    }
}

#[test]
fn straight_flight_position_error_matches_closed_form() {
    // Just before the heartbeat the DRM(F,P,W) error is R·|(cos x − 1, sin x − x)|.
    let (v, h) = (250.0, 3000.0);
    let mut r = DeadReckoner::new(DrAlgorithm::Fpw, DrThresholds::default()).unwrap();
    let s0 = equator_state(0.0, v, h).to_ecef().unwrap();
    r.record_sent(fdm_dis::WireState::new(&s0, DrAlgorithm::Fpw));
    let dt = 5.0 - DT;
    let err = r
        .error(&equator_state(dt, v, h).to_ecef().unwrap())
        .unwrap();
    let big_r = WGS84_A_M + h;
    let x = v / big_r * dt;
    let want = big_r * ((x.cos() - 1.0).powi(2) + (x.sin() - x).powi(2)).sqrt();
    // f32 velocity (250 m/s rounds by < 1e-5 m/s) over 5 s: < 1e-4 m.
    assert!(
        (err.position_m - want).abs() < 1e-4,
        "{} vs {want}",
        err.position_m
    );
    assert!((err.orientation_deg - x.to_degrees()).abs() < 1e-5);
    // The closed form itself: v²Δ²/(2R), under the 1 m threshold.
    assert!((want - v * v * dt * dt / (2.0 * big_r)).abs() < 1e-3 && want < 1.0);
}

/// Smallest x in (0, 1] with f(x) ≥ target, by bisection (f increasing).
fn solve(f: impl Fn(f64) -> f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    assert!(f(hi) > target);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) >= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Checks every interval between consecutive sends after the first.
fn assert_intervals(sends: &[(f64, SendReason)], want_s: f64, reason: SendReason, what: &str) {
    assert!(sends.len() > 3, "{what}: only {} sends", sends.len());
    for pair in sends.windows(2) {
        let gap = pair[1].0 - pair[0].0;
        assert_eq!(pair[1].1, reason, "{what}: {pair:?}");
        assert!(
            gap > want_s - 1e-6 && gap <= want_s + DT + 1e-6,
            "{what}: gap {gap} s, analytic {want_s} s"
        );
    }
}

#[test]
fn turn_triggers_updates_at_the_analytic_times() {
    let turn = Turn::coordinated(60.0, 30.0);
    let (w, r) = (turn.rate, turn.radius());
    let duration_s = 60.0;
    let frames = (duration_s / DT) as u32;

    // DRM(F,P,W): orientation error ΩΔ reaches 3° first.
    let t_fpw = 3f64.to_radians() / w;
    let x = w * t_fpw;
    let pos_err_then = r * ((x.sin() - x).powi(2) + (1.0 - x.cos()).powi(2)).sqrt();
    assert!(
        pos_err_then < 1.0,
        "precondition: position error {pos_err_then} m at 3°"
    );
    let mut fpw = publisher(DrAlgorithm::Fpw, DrThresholds::default());
    let sends_fpw = run(&mut fpw, frames, |t| turn.state(t));
    assert_intervals(&sends_fpw, t_fpw, SendReason::OrientationError, "FPW turn");

    // DRM(R,V,W): position error reaches 1 m first; orientation is exact.
    let rvw_err =
        |x: f64| r * ((x.sin() - x).powi(2) + (1.0 - x.cos() - x * x / 2.0).powi(2)).sqrt();
    let t_rvw = solve(rvw_err, 1.0) / w;
    let mut rvw = publisher(DrAlgorithm::Rvw, DrThresholds::default());
    let sends_rvw = run(&mut rvw, frames, |t| turn.state(t));
    assert_intervals(&sends_rvw, t_rvw, SendReason::PositionError, "RVW turn");

    let (cf, cr) = (fpw.counts(), rvw.counts());
    println!(
        "60 s turn, 60 m/s, bank 30° (rate {:.3}°/s, radius {r:.1} m), {} frames:\n  \
         DRM(F,P,W): {} PDUs ({} orientation, {} position, {} heartbeat), analytic interval {t_fpw:.4} s\n  \
         DRM(R,V,W): {} PDUs ({} orientation, {} position, {} heartbeat), analytic interval {t_rvw:.4} s",
        w.to_degrees(),
        cf.frames,
        cf.sent,
        cf.orientation,
        cf.position,
        cf.heartbeat,
        cr.sent,
        cr.orientation,
        cr.position,
        cr.heartbeat
    );
    // Counts follow from the intervals: 1 + floor(60 / interval_in_frames).
    // A send happens on the first frame with elapsed time > t (the error
    // equals the threshold at t exactly): every floor(t / DT) + 1 frames.
    let per = |t: f64| (t / DT).floor() as u64 + 1;
    assert_eq!(cf.sent, 1 + u64::from(frames) / per(t_fpw));
    assert_eq!(cr.sent, 1 + u64::from(frames) / per(t_rvw));
    assert!(cr.sent < cf.sent);
    // Both far above the 13 heartbeat-only PDUs of straight flight.
    assert!(cr.sent > 13);
}

#[test]
fn thresholds_are_configurable() {
    let turn = Turn::coordinated(60.0, 30.0);
    let frames = (30.0 / DT) as u32;
    // 6° and 10 m: the orientation still triggers first (position error at
    // 6° is r(1 − cos 6°) ≈ 3.5 m < 10 m).
    let t = DrThresholds {
        position_m: 10.0,
        orientation_deg: 6.0,
        heartbeat_s: 5.0,
    };
    let mut p = publisher(DrAlgorithm::Fpw, t);
    let sends = run(&mut p, frames, |x| turn.state(x));
    assert_intervals(
        &sends,
        6f64.to_radians() / turn.rate,
        SendReason::OrientationError,
        "6°",
    );

    // A 1 s heartbeat on straight flight.
    let t = DrThresholds {
        heartbeat_s: 1.0,
        ..DrThresholds::default()
    };
    let mut p = publisher(DrAlgorithm::Rvw, t);
    let sends = run(&mut p, (10.0 / DT) as u32, |x| {
        equator_state(x, 100.0, 500.0)
    });
    assert_eq!(sends.len(), 11);

    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        for t in [
            DrThresholds {
                position_m: bad,
                ..DrThresholds::default()
            },
            DrThresholds {
                orientation_deg: bad,
                ..DrThresholds::default()
            },
            DrThresholds {
                heartbeat_s: bad,
                ..DrThresholds::default()
            },
        ] {
            assert!(matches!(
                DeadReckoner::new(DrAlgorithm::Fpw, t),
                Err(DisOutputError::BadThreshold(_))
            ));
        }
    }
}

#[test]
fn clock_reset_and_bad_state() {
    let mut p = publisher(DrAlgorithm::Rvw, DrThresholds::default());
    let s = equator_state(10.0, 100.0, 500.0);
    assert_eq!(p.update(&s).unwrap().unwrap().reason, SendReason::First);
    assert!(p
        .update(&equator_state(10.5, 100.0, 500.0))
        .unwrap()
        .is_none());
    assert_eq!(
        p.update(&equator_state(0.0, 100.0, 500.0))
            .unwrap()
            .unwrap()
            .reason,
        SendReason::ClockReset
    );
    let mut bad = s;
    bad.position.lon_deg = f64::NAN;
    assert!(p.update(&bad).is_err());
    assert_eq!(p.counts().sent, 2);
}

#[test]
fn rotating_models_extrapolate_a_turn_exactly() {
    // After 2 s of the turn, DRM(R,*,W) orientation error is only the f32
    // rounding of the sent angles and rates (< 1e-4°); DRM(F,*,W) is off by
    // exactly the heading change.
    let turn = Turn::coordinated(60.0, 30.0);
    let s0 = turn.state(0.0).to_ecef().unwrap();
    let s2 = turn.state(2.0).to_ecef().unwrap();
    for (alg, want_deg) in [
        (DrAlgorithm::Rvw, 0.0),
        (DrAlgorithm::Rpw, 0.0),
        (DrAlgorithm::Fpw, (2.0 * turn.rate).to_degrees()),
        (DrAlgorithm::Fvw, (2.0 * turn.rate).to_degrees()),
    ] {
        let mut r = DeadReckoner::new(alg, DrThresholds::default()).unwrap();
        r.record_sent(fdm_dis::WireState::new(&s0, alg));
        let e = r.error(&s2).unwrap();
        assert!(
            (e.orientation_deg - want_deg).abs() < 1e-4,
            "{alg:?}: {e:?}"
        );
    }
    // Unused rates are zeroed on the wire.
    let w = fdm_dis::WireState::new(&s0, DrAlgorithm::Fpw);
    assert_eq!(
        (w.acceleration_m_s2, w.angular_velocity_rad_s),
        ([0.0; 3], [0.0; 3])
    );
    let w = fdm_dis::WireState::new(&s0, DrAlgorithm::Rvw);
    assert!(w.acceleration_m_s2 != [0.0; 3] && w.angular_velocity_rad_s != [0.0; 3]);
}

/// The R models' orientation, as `extrapolate` documents it:
/// `C₀ · exp([ω]× Δt)`, the body turning at its sent body-axis rate ω for
/// Δt. The exponential of a rotation vector is Rodrigues' rotation about
/// ω by |ω| Δt, here nalgebra's `Rotation3::from_scaled_axis` (the same
/// formula, the platform's sine and cosine: within 1e-15 per entry). The
/// rates have all three components, in both senses, up to more than half a
/// turn; a zero rate holds the orientation exactly, and the F models hold
/// it whatever the rate.
#[test]
fn rotating_models_turn_about_the_sent_rate_vector() {
    use nalgebra::Rotation3;
    let s = AircraftState::new(
        3.0,
        Geodetic {
            lat_deg: 51.5,
            lon_deg: -2.25,
            alt_m: 1500.0,
        },
        Attitude {
            heading_deg: 123.0,
            pitch_deg: 7.0,
            roll_deg: -18.0,
        },
        Vector3::new(40.0, -25.0, 3.0),
    )
    .to_ecef()
    .unwrap();
    for w in [
        [0.3_f32, -0.2, 0.5],
        [-1.25, 0.75, 0.125],
        [0.02, 0.9, -0.4],
        [2.0, 1.5, -2.5],
    ] {
        let mut sent = fdm_dis::WireState::new(&s, DrAlgorithm::Rvw);
        sent.angular_velocity_rad_s = w;
        let c0 = sent.orientation().body_to_ecef();
        let w = Vector3::from(w.map(f64::from));
        for dt in [0.05, 0.5, 1.0] {
            let want = c0 * Rotation3::from_scaled_axis(w * dt).into_inner();
            for alg in [DrAlgorithm::Rvw, DrAlgorithm::Rpw] {
                let (_, got) = fdm_dis::extrapolate(alg, &sent, dt);
                assert!(
                    (got - want).amax() < 1e-14,
                    "{alg:?}, ω {w:?}, Δt {dt}: {got} vs {want}"
                );
            }
            for alg in [DrAlgorithm::Fvw, DrAlgorithm::Fpw] {
                assert_eq!(fdm_dis::extrapolate(alg, &sent, dt).1, c0, "{alg:?}");
            }
        }
    }
    let mut still = fdm_dis::WireState::new(&s, DrAlgorithm::Rvw);
    still.angular_velocity_rad_s = [0.0; 3];
    let c0 = still.orientation().body_to_ecef();
    assert_eq!(fdm_dis::extrapolate(DrAlgorithm::Rvw, &still, 2.0).1, c0);
}

/// What a reckoner says of itself (docs of `DeadReckoner`): the model and
/// thresholds it was made with (neither the defaults), nothing sent and no
/// error before the first PDU, then the PDU recorded, and the error of a
/// truth whose distance from the extrapolation is known exactly: a DRM(F,P,W)
/// receiver puts the aircraft at `P₀ + V₀ Δt` with the orientation held, so
/// a truth 2 s later that far along plus (3, 4, 0) m, same orientation, is
/// 5 m and 0° off after 2 s. (Every number is exact in binary and in the
/// PDU's f32 fields, so the comparisons are exact.)
#[test]
fn a_reckoner_reports_its_model_its_thresholds_its_last_pdu_and_its_error() {
    use fdm_dis::{EcefState, WireState};
    use nalgebra::Matrix3;
    let thresholds = DrThresholds {
        position_m: 2.5,
        orientation_deg: 7.0,
        heartbeat_s: 9.0,
    };
    let mut reckoner = DeadReckoner::new(DrAlgorithm::Fpw, thresholds).unwrap();
    assert_eq!(reckoner.algorithm(), DrAlgorithm::Fpw);
    assert_eq!(reckoner.thresholds(), thresholds);
    assert!(reckoner.last_sent().is_none());

    let location_m = Vector3::new(WGS84_A_M, 0.0, 0.0);
    let velocity_m_s = Vector3::new(100.0, -50.0, 25.0);
    let state = |time_s: f64, location_m: Vector3<f64>| {
        EcefState::new(
            time_s,
            location_m,
            Matrix3::identity(),
            velocity_m_s,
            Vector3::zeros(),
            Vector3::zeros(),
        )
    };
    let sent = state(10.0, location_m);
    assert_eq!(reckoner.error(&sent), None);
    let wire = WireState::new(&sent, DrAlgorithm::Fpw);
    reckoner.record_sent(wire);
    assert_eq!(reckoner.last_sent(), Some(&wire));

    let truth = state(
        12.0,
        location_m + velocity_m_s * 2.0 + Vector3::new(3.0, 4.0, 0.0),
    );
    let error = reckoner.error(&truth).unwrap();
    assert_eq!(error.elapsed_s, 2.0);
    assert_eq!(error.position_m, 5.0);
    assert_eq!(error.orientation_deg, 0.0);
    // 5 m is above the 2.5 m threshold: due, for its position.
    assert_eq!(reckoner.check(&truth), Some(SendReason::PositionError));

    // Each threshold landed on exactly ("more than the threshold" is due,
    // the threshold itself is not): the same time as the PDU is not a clock
    // that went back; 2.5 m off is not due; an orientation off by exactly the
    // threshold is not due. One step beyond each is.
    assert_eq!(reckoner.check(&sent), None);
    assert_eq!(
        reckoner.check(&state(10.0 - 1.0 / 64.0, location_m)),
        Some(SendReason::ClockReset)
    );
    let along = location_m + velocity_m_s * 2.0;
    assert_eq!(
        reckoner.check(&state(12.0, along + Vector3::new(1.5, 2.0, 0.0))),
        None
    );
    assert_eq!(
        reckoner.check(&state(12.0, along + Vector3::new(1.5, 2.0 + 1e-9, 0.0))),
        Some(SendReason::PositionError)
    );
    let turned = nalgebra::Rotation3::from_scaled_axis(Vector3::new(0.0, 0.0, 0.1)).into_inner();
    let angle_deg = fdm_dis::rotation_angle_between(&Matrix3::identity(), &turned).to_degrees();
    // A reckoner whose orientation threshold is `orientation_deg`, with the
    // same PDU.
    let reckoner_at = |orientation_deg: f64| {
        let thresholds = DrThresholds {
            orientation_deg,
            ..thresholds
        };
        let mut r = DeadReckoner::new(DrAlgorithm::Fpw, thresholds).unwrap();
        r.record_sent(wire);
        r
    };
    let mut truth = state(12.0, along);
    truth.body_to_ecef = turned;
    assert_eq!(reckoner_at(angle_deg).check(&truth), None);
    assert_eq!(
        reckoner_at(angle_deg * (1.0 - 1e-12)).check(&truth),
        Some(SendReason::OrientationError)
    );
}
