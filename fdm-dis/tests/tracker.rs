//! One aircraft's DIS output through the public API of `fdm_dis::tracker`
//! (its module documentation, docs/dis.md), written from what the docs
//! promise rather than from the numbers the code gives today:
//!
//! * [`Placement`] keeps the origin it was made with, and its model-NED to
//!   ECEF rotation is the origin's NED axes ([`ned_to_ecef_rotation`]).
//! * [`Tracker`]'s rates: the acceleration is the change of the ECEF
//!   velocity over the frame, the body angular velocity
//!   `log(C_prev⁻¹ C_now) / Δt`; zero on the first frame and whenever the
//!   clock did not go forwards (the same time again, or back).
//! * [`Tracker::update`] is exactly the whole computation
//!   ([`Tracker::with_rates`] of [`Placement::place`] given to
//!   [`EntityPublisher::update_ecef`]): same decisions, bytes, counts and
//!   errors, also for the frames whose rates overflow (a frame shorter than
//!   any flight makes, speeds near the largest `f64`, a previous frame that
//!   was not finite), which the lazy path must hand to the whole one.
//! * [`Tally`] counts each PDU under its reason, its bytes, failed sends
//!   with the first failure's message, and merges every count.

use std::net::UdpSocket;
use std::time::Duration;

use fdm_core::geodesy::{Attitude, GeodeticOrigin};
use fdm_core::model::{FlightView, Model};
use fdm_core::palmer::Palmer;
use fdm_dis::{
    ned_to_ecef_rotation, rotation_vector, AircraftKind, DisOutputError, DrThresholds, Due,
    EcefState, EntityConfig, EntityIdentity, EntityPublisher, Marking, Placement, SendReason,
    Tally, Tracker, UdpSender,
};
use nalgebra::{Matrix3, Rotation3, Vector3};

fn config() -> EntityConfig {
    EntityConfig::new(
        EntityIdentity::new(1, 1, 7).unwrap(),
        AircraftKind::CESSNA_172_SKYHAWK,
        Marking::new("T7").unwrap(),
    )
}

fn tracker() -> Tracker {
    Tracker::new(config(), DrThresholds::default()).unwrap()
}

/// An origin away from the default one (southern and eastern hemispheres),
/// so that a placement that forgot its origin shows.
fn origin() -> GeodeticOrigin {
    GeodeticOrigin::new(-33.946, 151.177, 6.0).unwrap()
}

#[test]
fn a_placement_keeps_its_origin_and_the_origins_ned_axes() {
    let origin = origin();
    let placement = Placement::new(origin);
    assert_eq!(placement.origin(), &origin);
    let g = origin.geodetic();
    assert_eq!(
        placement.model_ned_to_ecef(),
        &ned_to_ecef_rotation(g.lat_deg, g.lon_deg)
    );
}

/// A state at `time_s` with this velocity and orientation (rates zero: the
/// tracker makes them).
fn state(time_s: f64, velocity_m_s: Vector3<f64>, body_to_ecef: Matrix3<f64>) -> EcefState {
    EcefState::new(
        time_s,
        Vector3::new(-4_646_000.0, 2_553_000.0, -3_534_000.0),
        body_to_ecef,
        velocity_m_s,
        Vector3::zeros(),
        Vector3::zeros(),
    )
}

/// The rates of consecutive frames as the docs define them, against
/// independent constructions: the acceleration `(v₁ - v₀)/Δt` to 1e-12
/// relative (one subtraction and one division), the angular velocity of a
/// body turned by nalgebra's `exp(ω Δt)` in body axes to 1e-9 rad/s (the
/// rotation vector's rounding, 1e-12 rad, over a frame of 1/30 s, with
/// room for the matrix products). Zero on the first frame, when the clock
/// stands still and when it goes back; the frame after a reset takes its
/// rates from the frame that reset.
#[test]
fn rates_are_the_change_over_the_frame_and_zero_unless_the_clock_goes_forwards() {
    let dt = 1.0 / 30.0;
    let omega_body = Vector3::new(0.05, -0.3, 0.6);
    let c0 = Rotation3::from_euler_angles(0.2, -0.4, 1.1).into_inner();
    let c1 = c0 * Rotation3::from_scaled_axis(omega_body * dt).into_inner();
    let v0 = Vector3::new(40.0, -12.0, 3.0);
    let v1 = Vector3::new(40.5, -12.25, 2.0);

    let mut t = tracker();
    let first = t.with_rates(state(10.0, v0, c0));
    assert_eq!(first.acceleration_m_s2, Vector3::zeros());
    assert_eq!(first.angular_velocity_body_rad_s, Vector3::zeros());

    let next = t.with_rates(state(10.0 + dt, v1, c1));
    let frame_s = (10.0 + dt) - 10.0;
    let acceleration = (v1 - v0) / frame_s;
    assert!(
        (next.acceleration_m_s2 - acceleration).norm() <= 1e-12 * acceleration.norm(),
        "{}",
        next.acceleration_m_s2
    );
    assert!(
        (next.angular_velocity_body_rad_s - omega_body).norm() < 1e-9,
        "{}",
        next.angular_velocity_body_rad_s
    );
    // The other state fields pass through untouched.
    assert_eq!(next.velocity_m_s, v1);
    assert_eq!(next.body_to_ecef, c1);

    // The same time again (a paused run resending its frame), with another
    // velocity and orientation: zero rates, not a division by zero.
    let stood = t.with_rates(state(10.0 + dt, v0, c0));
    assert_eq!(stood.acceleration_m_s2, Vector3::zeros());
    assert_eq!(stood.angular_velocity_body_rad_s, Vector3::zeros());

    // Back in time (a reset): zero rates again.
    let reset = t.with_rates(state(2.0, v1, c1));
    assert_eq!(reset.acceleration_m_s2, Vector3::zeros());
    assert_eq!(reset.angular_velocity_body_rad_s, Vector3::zeros());

    // The frame after the reset is measured from the reset frame.
    let after = t.with_rates(state(2.0 + dt, v0, c0));
    let back = (v0 - v1) / ((2.0 + dt) - 2.0);
    assert!((after.acceleration_m_s2 - back).norm() <= 1e-12 * back.norm());
    let undo = rotation_vector(&(c1.transpose() * c0)) / ((2.0 + dt) - 2.0);
    assert!((after.angular_velocity_body_rad_s - undo).norm() < 1e-9);
    assert!((after.angular_velocity_body_rad_s + omega_body).norm() < 1e-9);
}

/// A frame of Palmer's aircraft in flight, to edit.
fn view() -> FlightView {
    let aircraft = Palmer::default_aircraft();
    let (controls, state) = Palmer::fleet_member(3);
    let state = Palmer::step(&aircraft, &controls, &state, 1.0 / 30.0);
    Palmer::view(&aircraft, &controls, &state)
}

/// The view at `time_s` with this model-frame velocity.
fn at(time_s: f64, velocity_mps: Vector3<f64>) -> FlightView {
    FlightView {
        time_s,
        velocity_mps,
        ..view()
    }
}

type Outcome = Result<Option<(SendReason, Vec<u8>)>, DisOutputError>;

/// Flies `views` through [`Tracker::update`] and through the whole
/// computation it stands for (a second tracker's [`Tracker::with_rates`] of
/// [`Placement::place`], given to an [`EntityPublisher`] of the same
/// configuration), frame by frame; returns the outcomes, asserting they
/// agree, and that the counts agree at the end.
fn lazy_and_whole(views: &[FlightView]) -> Vec<Outcome> {
    let placement = Placement::new(origin());
    let mut lazy = tracker();
    let mut rates = tracker();
    let mut whole = EntityPublisher::new(config(), DrThresholds::default()).unwrap();
    let mut outcomes = Vec::new();
    for (frame, view) in views.iter().enumerate() {
        let expected: Outcome = whole
            .update_ecef(&rates.with_rates(placement.place(view)))
            .map(|d| d.map(|d| (d.reason, d.bytes.to_vec())));
        let got: Outcome = lazy
            .update(view, &placement)
            .map(|d| d.map(|d| (d.reason, d.bytes.to_vec())));
        assert_eq!(got, expected, "frame {frame}");
        outcomes.push(got);
    }
    assert_eq!(lazy.counts(), whole.counts());
    outcomes
}

fn is_acceleration_error(outcome: &Outcome) -> bool {
    matches!(outcome, Err(DisOutputError::NonFinite("acceleration_m_s2")))
}

/// A frame far shorter than any a run makes (2e-310 s, subnormal) after a
/// frame that was sent: its acceleration overflows to infinity, so the
/// frame is refused as the whole computation refuses it, not passed over
/// as "nothing due" (the position hardly moved). The times straddle zero,
/// so that a frame length made any other way than their difference (their
/// sum, their quotient) is not positive.
#[test]
fn a_frame_too_short_for_finite_rates_is_refused_like_the_whole_computation() {
    let v = view().velocity_mps;
    let outcomes = lazy_and_whole(&[at(-1e-310, v), at(1e-310, v + Vector3::new(1.0, 0.0, 0.0))]);
    assert!(matches!(outcomes[0], Ok(Some((SendReason::First, _)))));
    assert!(is_acceleration_error(&outcomes[1]), "{:?}", outcomes[1]);
}

/// Speeds near the largest `f64` (1e308 m/s) on frames where nothing is
/// due (the aircraft is where the last PDU's dead reckoning puts it, which
/// does not read the frame's own velocity): the change of velocity over the
/// frame overflows, so each frame is refused, as the whole computation
/// refuses it, not passed over. The huge speed this frame, then the
/// previous frame's, then both (one way and the other), then neither.
#[test]
fn speeds_whose_change_overflows_are_refused_like_the_whole_computation() {
    let dt = 1.0 / 30.0;
    let start = view();
    let v0 = start.velocity_mps;
    let huge = Vector3::new(1e308, 0.0, 0.0);
    // Where dead reckoning from the first frame puts the aircraft at frame k.
    let frame = |k: f64, velocity_mps: Vector3<f64>| FlightView {
        time_s: 1.0 + k * dt,
        position_m: start.position_m + v0 * (k * dt),
        velocity_mps,
        ..start
    };
    let outcomes = lazy_and_whole(&[
        frame(0.0, v0),
        frame(1.0, huge),
        frame(2.0, -huge),
        frame(3.0, v0),
        frame(4.0, v0),
    ]);
    assert!(matches!(outcomes[0], Ok(Some((SendReason::First, _)))));
    for (k, outcome) in outcomes.iter().enumerate().take(4).skip(1) {
        assert!(is_acceleration_error(outcome), "frame {k}: {outcome:?}");
    }
    assert!(matches!(outcomes[4], Ok(None)), "{:?}", outcomes[4]);
}

/// A frame whose attitude is not finite is refused; the next, finite frame
/// measures its turn from that frame's orientation, so its angular velocity
/// is not finite either and it is refused too (both ways), not passed over.
/// The frame after it measures from a finite frame again and is accepted.
#[test]
fn a_frame_after_a_non_finite_orientation_is_refused_like_the_whole_computation() {
    let dt = 1.0 / 30.0;
    // At rest, so that no frame is due by its position.
    let v = Vector3::zeros();
    let mut broken = at(1.0 + dt, v);
    broken.attitude = Attitude {
        roll_deg: f64::NAN,
        ..broken.attitude
    };
    let outcomes = lazy_and_whole(&[
        at(1.0, v),
        broken,
        at(1.0 + 2.0 * dt, v),
        at(1.0 + 3.0 * dt, v),
    ]);
    assert!(matches!(outcomes[0], Ok(Some((SendReason::First, _)))));
    assert!(
        matches!(outcomes[1], Err(DisOutputError::NonFinite("body_to_ecef"))),
        "{:?}",
        outcomes[1]
    );
    assert!(
        matches!(
            outcomes[2],
            Err(DisOutputError::NonFinite("angular_velocity_body_rad_s"))
        ),
        "{:?}",
        outcomes[2]
    );
    assert!(matches!(outcomes[3], Ok(None)), "{:?}", outcomes[3]);
}

/// The same time twice with the aircraft moved far away: a PDU is due
/// (position error) and carries zero rates, not a division by zero.
#[test]
fn a_due_frame_at_the_same_time_is_sent_with_zero_rates() {
    let v = view().velocity_mps;
    let mut moved = at(1.0, v);
    moved.position_m.x += 500.0;
    let outcomes = lazy_and_whole(&[at(1.0, v), moved]);
    assert!(matches!(outcomes[0], Ok(Some((SendReason::First, _)))));
    assert!(matches!(outcomes[1], Ok(Some(_))), "{:?}", outcomes[1]);
}

/// A receiver on 127.0.0.1 and a sender to it.
fn link() -> (UdpSocket, UdpSender) {
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let tx = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
    (rx, tx)
}

/// Each reason is counted under its own name (a reset with the first
/// PDUs), every PDU and its bytes once, each datagram arriving as given.
#[test]
fn a_tally_counts_each_pdu_under_its_reason() {
    let (rx, tx) = link();
    let mut tally = Tally::default();
    let sends = [
        (SendReason::First, 144),
        (SendReason::ClockReset, 144),
        (SendReason::PositionError, 100),
        (SendReason::PositionError, 10),
        (SendReason::OrientationError, 20),
        (SendReason::Heartbeat, 30),
        (SendReason::Heartbeat, 31),
        (SendReason::Heartbeat, 32),
    ];
    let mut buf = [0u8; 2048];
    for (i, (reason, len)) in sends.into_iter().enumerate() {
        let bytes = vec![u8::try_from(i).unwrap(); len];
        tally.send(
            &tx,
            &Due {
                reason,
                bytes: &bytes,
            },
        );
        let n = rx.recv(&mut buf).unwrap();
        assert_eq!(&buf[..n], &bytes[..]);
    }
    assert_eq!(tally.pdus, 8);
    assert_eq!(tally.bytes, 144 + 144 + 100 + 10 + 20 + 30 + 31 + 32);
    assert_eq!(
        (
            tally.reasons.first,
            tally.reasons.position,
            tally.reasons.orientation,
            tally.reasons.heartbeat
        ),
        (2, 2, 1, 3)
    );
    assert_eq!((tally.failed, tally.invalid), (0, 0));
    assert!(tally.first_failure.is_none());
}

/// A send the OS refuses (a datagram larger than UDP carries) is counted
/// as failed, not as a PDU or bytes, under its reason still; the first
/// failure's message is kept and names the target, later ones do not
/// replace it. A frame that cannot be sent at all counts as invalid.
#[test]
fn a_tally_counts_failures_and_keeps_the_first_message() {
    let (_rx, tx) = link();
    let mut tally = Tally::default();
    let too_big = vec![0u8; 70_000];
    for reason in [SendReason::Heartbeat, SendReason::PositionError] {
        tally.send(
            &tx,
            &Due {
                reason,
                bytes: &too_big,
            },
        );
    }
    assert_eq!((tally.pdus, tally.bytes, tally.failed), (0, 0, 2));
    assert_eq!((tally.reasons.heartbeat, tally.reasons.position), (1, 1));
    let first = tally.first_failure.clone().unwrap();
    assert!(first.contains(&tx.target().to_string()), "{first}");
    tally.invalid(&DisOutputError::NonFinite("location_m"));
    assert_eq!(tally.invalid, 1);
    assert_eq!(tally.first_failure.as_deref(), Some(first.as_str()));

    let mut fresh = Tally::default();
    fresh.invalid(&DisOutputError::NonFinite("location_m"));
    assert!(fresh.first_failure.unwrap().contains("location_m"));
}

/// Merging adds every count (each field a different number, so that one
/// added to another's place shows) and keeps this tally's failure message,
/// or takes the other's when this has none.
#[test]
fn merging_tallies_adds_every_count() {
    let tally = |base: u64, failure: Option<&str>| {
        let mut t = Tally::default();
        t.pdus = base;
        t.bytes = base * 2;
        t.failed = base * 3;
        t.invalid = base * 4;
        t.first_failure = failure.map(str::to_owned);
        t.reasons.first = base * 5;
        t.reasons.position = base * 6;
        t.reasons.orientation = base * 7;
        t.reasons.heartbeat = base * 8;
        t
    };
    let counts = |t: &Tally| {
        [
            t.pdus,
            t.bytes,
            t.failed,
            t.invalid,
            t.reasons.first,
            t.reasons.position,
            t.reasons.orientation,
            t.reasons.heartbeat,
        ]
    };
    let mut a = tally(1, None);
    a.merge(tally(100, Some("theirs")));
    assert_eq!(counts(&a), [101, 202, 303, 404, 505, 606, 707, 808]);
    assert_eq!(a.first_failure.as_deref(), Some("theirs"));

    let mut b = tally(10, Some("ours"));
    b.merge(tally(1_000, Some("theirs")));
    assert_eq!(
        counts(&b),
        [1_010, 2_020, 3_030, 4_040, 5_050, 6_060, 7_070, 8_080]
    );
    assert_eq!(b.first_failure.as_deref(), Some("ours"));
}
