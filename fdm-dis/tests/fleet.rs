//! The fleet publisher through its public API (`fdm_dis::fleet`,
//! docs/dis.md): [`FleetPublisher::publish`], `publish_screened` and the
//! pieces of [`FleetPublisher::screened_pieces`] send, over UDP on
//! 127.0.0.1, exactly the datagrams that each aircraft's own [`Tracker`]
//! gives for its views, one aircraft after the other; their counts are the
//! trackers' counts. The fleet is more than one batch of [`FLEET_BATCH`]
//! aircraft, and the aircraft offered sit on both sides of the batch
//! boundary, so that an aircraft given another's view, or a batch's
//! aircraft numbered from the wrong place, shows in the bytes (each PDU
//! carries its tracker's entity id and its view's position).

use std::net::UdpSocket;
use std::time::Duration;

use fdm_core::geodesy::{Attitude, GeodeticOrigin};
use fdm_core::model::{FlightView, Model};
use fdm_core::palmer::Palmer;
use fdm_dis::{
    AircraftKind, DrThresholds, EntityIdentity, FleetPublisher, Marking, Placement,
    PublisherCounts, ReasonCounts, Rough, SendReason, Tally, Tracker, UdpSender, FLEET_BATCH,
};
use fdm_dis::{DeadReckoner, DrAlgorithm, WireState};
use fdm_dis::{EntityConfig, ScreenedPiece};
use nalgebra::Vector3;

/// Aircraft in the fleet: one full batch and six more.
const N: usize = FLEET_BATCH + 6;
/// The aircraft given a view: both ends of the first batch, the first
/// aircraft of the second and its last. Every other aircraft is never
/// offered (`None`), so a frame sends few datagrams (none is dropped by a
/// full receive buffer).
const OFFERED: [usize; 10] = [0, 1, 2, 3, 500, 1022, 1023, 1024, 1025, N - 1];
/// Frames flown, 30 per second.
const FRAMES: usize = 150;

/// Aircraft `i`'s tracker: entity `i + 1`, so its PDUs name it.
fn trackers() -> Vec<Tracker> {
    (0..N)
        .map(|i| {
            let config = EntityConfig::new(
                EntityIdentity::new(1, 1, u16::try_from(i + 1).unwrap()).unwrap(),
                AircraftKind::CESSNA_172_SKYHAWK,
                Marking::new(&format!("F{i}")).unwrap(),
            );
            Tracker::new(config, DrThresholds::default()).unwrap()
        })
        .collect()
}

/// Each frame's views of the offered aircraft (Palmer's fleet members,
/// each flying its own turn): `views[frame][i]`, `None` for an aircraft not
/// offered that frame. Aircraft 2 is left out on frames 30 to 39; aircraft
/// 1025 diverges (NaN) at frame 100.
fn views() -> Vec<Vec<Option<FlightView>>> {
    let aircraft = Palmer::default_aircraft();
    let mut members: Vec<_> = OFFERED
        .iter()
        .map(|&i| (i, Palmer::fleet_member(i)))
        .collect();
    (0..FRAMES)
        .map(|frame| {
            let mut row = vec![None; N];
            for (i, (controls, state)) in &mut members {
                *state = Palmer::step(&aircraft, controls, state, 1.0 / 30.0);
                if *i == 1025 && frame == 100 {
                    state.position_m.x = f64::NAN;
                }
                let offered = *i != 2 || !(30..40).contains(&frame);
                row[*i] = offered.then(|| Palmer::view(&aircraft, controls, state));
            }
            row
        })
        .collect()
}

/// What a frame must send and count: each offered aircraft's own tracker
/// updated alone, in fleet order.
struct Expected {
    datagrams: Vec<Vec<u8>>,
    reasons: ReasonCounts,
    invalid: u64,
}

fn expected_frame(
    trackers: &mut [Tracker],
    row: &[Option<FlightView>],
    placement: &Placement,
) -> Expected {
    let mut e = Expected {
        datagrams: Vec::new(),
        reasons: ReasonCounts::default(),
        invalid: 0,
    };
    for (t, v) in trackers.iter_mut().zip(row) {
        let Some(v) = v else { continue };
        match t.update(v, placement) {
            Ok(Some(d)) => {
                match d.reason {
                    SendReason::First | SendReason::ClockReset => e.reasons.first += 1,
                    SendReason::PositionError => e.reasons.position += 1,
                    SendReason::OrientationError => e.reasons.orientation += 1,
                    SendReason::Heartbeat => e.reasons.heartbeat += 1,
                }
                e.datagrams.push(d.bytes.to_vec());
            }
            Ok(None) => {}
            Err(_) => e.invalid += 1,
        }
    }
    e.datagrams.sort();
    e
}

/// A receiver on 127.0.0.1 and a sender to it.
fn link() -> (UdpSocket, UdpSender) {
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let tx = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
    (rx, tx)
}

/// The `count` datagrams waiting at `rx` (sorted), and then no more.
fn received(rx: &UdpSocket, count: usize) -> Vec<Vec<u8>> {
    let mut buf = [0u8; 2048];
    let mut got: Vec<Vec<u8>> = (0..count)
        .map(|_| {
            let n = rx.recv(&mut buf).expect("a datagram on loopback");
            buf[..n].to_vec()
        })
        .collect();
    // Loopback delivers a datagram before its send returns: anything more
    // is already there.
    rx.set_nonblocking(true).unwrap();
    let extra = rx.recv(&mut buf);
    assert!(extra.is_err(), "a datagram more than due: {extra:?}");
    rx.set_nonblocking(false).unwrap();
    got.sort();
    got
}

fn assert_tally(tally: &Tally, e: &Expected, what: &str) {
    let bytes: usize = e.datagrams.iter().map(Vec::len).sum();
    assert_eq!(tally.pdus, e.datagrams.len() as u64, "{what}: PDUs");
    assert_eq!(tally.bytes, bytes as u64, "{what}: bytes");
    assert_eq!(tally.reasons, e.reasons, "{what}: reasons");
    assert_eq!(
        (tally.failed, tally.invalid),
        (0, e.invalid),
        "{what}: failed, invalid"
    );
    assert_eq!(
        tally.first_failure.is_some(),
        e.invalid > 0,
        "{what}: {tally:?}"
    );
}

/// The rough frame of a view: its own numbers (well within the tolerance);
/// none for a non-finite view (no rough frame can be made for it).
fn rough_of(v: &FlightView) -> Option<Rough> {
    let r = Rough {
        time_s: v.time_s,
        position_m: v.position_m,
        velocity_mps: v.velocity_mps,
        body_to_ned: v.attitude.body_to_ned(),
    };
    (r.position_m
        .iter()
        .chain(&r.velocity_mps)
        .chain(r.body_to_ned.iter())
        .all(|x| x.is_finite()))
    .then_some(r)
}

/// A screened input: the aircraft's index (checked against the index
/// `rough` and `view` are told) and its view.
type Input = (usize, FlightView);

/// `rough` as the screened publishers document it: `out[k]` for aircraft
/// `first + k`, whose input is `states[k]`.
fn rough(first: usize, states: &[Option<Input>], out: &mut [Option<Rough>]) {
    assert_eq!(states.len(), out.len());
    for (k, (s, o)) in states.iter().zip(out.iter_mut()).enumerate() {
        *o = s.and_then(|(i, v)| {
            assert_eq!(
                i,
                first + k,
                "aircraft {}'s input for aircraft {i}",
                first + k
            );
            rough_of(&v)
        });
    }
}

/// `view(i, s)`: the exact view of aircraft `i` with input `s`.
fn view(i: usize, s: &Input) -> FlightView {
    assert_eq!(i, s.0, "aircraft {}'s input given as aircraft {i}'s", s.0);
    s.1
}

#[test]
fn len_and_is_empty_count_the_trackers() {
    let fleet = FleetPublisher::new(trackers());
    assert_eq!(fleet.len(), N);
    assert!(!fleet.is_empty());
    let one = FleetPublisher::new(trackers().into_iter().skip(N - 1).collect());
    assert_eq!((one.len(), one.is_empty()), (1, false));
    for empty in [FleetPublisher::new(Vec::new()), FleetPublisher::default()] {
        assert_eq!((empty.len(), empty.is_empty()), (0, true));
    }
}

/// `publish`, `publish_screened` and the pieces of `screened_pieces`
/// (published one after the other, seven aircraft a piece) send each frame
/// the datagrams of the trackers updated alone, count them in their tally,
/// and leave each aircraft's counts as its tracker's (an aircraft never
/// offered: no frame at all).
#[test]
fn every_way_of_publishing_sends_what_each_tracker_sends_alone() {
    let placement = Placement::new(GeodeticOrigin::default());
    let views = views();
    let mut alone = trackers();
    let mut whole = FleetPublisher::new(trackers());
    let mut screened = FleetPublisher::new(trackers());
    let mut pieces = FleetPublisher::new(trackers());
    let (rx_whole, tx_whole) = link();
    let (rx_screened, tx_screened) = link();
    let (rx_pieces, tx_pieces) = link();
    let (mut last_screened, mut last_pieces) = (Vec::new(), Vec::new());
    let mut sent = 0;
    for (frame, row) in views.iter().enumerate() {
        let e = expected_frame(&mut alone, row, &placement);
        sent += e.datagrams.len();
        let input = |i: usize| row[i].map(|v| (i, v));

        let tally = whole.publish(&tx_whole, &placement, |i| row[i]);
        assert_eq!(
            received(&rx_whole, e.datagrams.len()),
            e.datagrams,
            "publish, frame {frame}"
        );
        assert_tally(&tally, &e, &format!("publish, frame {frame}"));

        let tally = screened.publish_screened(
            &tx_screened,
            &placement,
            &mut last_screened,
            input,
            rough,
            view,
        );
        assert_eq!(
            received(&rx_screened, e.datagrams.len()),
            e.datagrams,
            "publish_screened, frame {frame}"
        );
        assert_tally(&tally, &e, &format!("publish_screened, frame {frame}"));

        let mut tally = Tally::default();
        for mut piece in pieces.screened_pieces(&placement, &mut last_pieces, 7) {
            let states: Vec<_> = (piece.first()..piece.first() + piece.len())
                .map(input)
                .collect();
            tally.merge(piece.publish(&tx_pieces, &states, rough, view));
        }
        assert_eq!(
            received(&rx_pieces, e.datagrams.len()),
            e.datagrams,
            "pieces, frame {frame}"
        );
        assert_tally(&tally, &e, &format!("pieces, frame {frame}"));
    }
    // Every offered aircraft sent its first PDU, and the turns sent more.
    assert!(sent > 2 * OFFERED.len(), "{sent} PDUs");
    for (i, tracker) in alone.iter().enumerate() {
        let own = tracker.counts();
        if !OFFERED.contains(&i) {
            assert_eq!(own, PublisherCounts::default(), "aircraft {i}");
        }
        assert_eq!(whole.counts(i), Some(own), "publish: aircraft {i}");
        assert_eq!(
            screened.counts(i),
            Some(own),
            "publish_screened: aircraft {i}"
        );
        assert_eq!(pieces.counts(i), Some(own), "pieces: aircraft {i}");
    }
    // The screen cleared most frames: counted, though no tracker saw them.
    let quiet = alone[0].counts();
    assert!(quiet.frames > 4 * quiet.sent, "{quiet:?}");
    assert_eq!(whole.counts(N), None);
    assert_eq!(screened.counts(N), None);
}

/// The pieces: `piece` aircraft each in fleet order, the last with the
/// rest, at least one aircraft a piece; a piece's `first`, `len` and
/// `is_empty`.
#[test]
fn screened_pieces_cut_the_fleet_in_order() {
    let placement = Placement::new(GeodeticOrigin::default());
    let mut fleet = FleetPublisher::new(trackers());
    let mut last: Vec<Option<Input>> = Vec::new();
    for per in [1, 7, FLEET_BATCH, N, N + 1] {
        let pieces = fleet.screened_pieces(&placement, &mut last, per);
        assert_eq!(pieces.len(), N.div_ceil(per), "pieces of {per}");
        for (c, p) in pieces.iter().enumerate() {
            let want = per.min(N - c * per);
            assert_eq!(
                (p.first(), p.len(), p.is_empty()),
                (c * per, want, false),
                "pieces of {per}, {c}"
            );
        }
        drop(pieces);
        assert_eq!(last.len(), N, "`last` is resized to the fleet");
    }
    let pieces: Vec<ScreenedPiece<'_, Input>> = fleet.screened_pieces(&placement, &mut last, 0);
    assert_eq!(pieces.len(), N, "a piece of 0 is a piece of 1");
    assert_eq!((pieces[N - 1].first(), pieces[N - 1].len()), (N - 1, 1));
    let mut empty = FleetPublisher::new(Vec::new());
    assert!(empty.screened_pieces(&placement, &mut last, 7).is_empty());
}

/// Palmer's fleet member 0 as it starts: the view the synthetic flights
/// below edit (their time, position, velocity and attitude).
fn member_zero_view() -> FlightView {
    let (controls, state) = Palmer::fleet_member(0);
    Palmer::view(&Palmer::default_aircraft(), &controls, &state)
}

/// Aircraft whose attitude steps or whose turn stops: the frames where the
/// receivers' extrapolation (which turns the last PDU's orientation by its
/// angular velocity) and the truth part ways without the truth leaving the
/// last PDU's orientation. Aircraft `k` flies at 50 m/s; the odd ones turn
/// at 6°/s and then stop; at its step frame each rolls by its own step
/// (2° to 20°, both ways), and one holds wings level all along. The step
/// makes a PDU whose angular velocity is the step over one frame (up to
/// 10 rad/s, under the screen's half-radian turn a frame), and the truth
/// then holds still: a screen that compared the truth with the PDU's
/// orientation unturned (or turned wrongly) would see nothing and clear the
/// frames where the tracker sends. `views[frame][k]`, 300 frames at 30 Hz.
fn stepping_views() -> Vec<Vec<Option<FlightView>>> {
    let base = member_zero_view();
    let roll_steps_deg = [2.0, 5.0, 10.0, 20.0, -8.0, 15.0, 0.0, -12.0];
    let dt = 1.0 / 30.0;
    let mut position: Vec<Vector3<f64>> = (0..roll_steps_deg.len())
        .map(|k| Vector3::new(100.0 * k as f64, 0.0, 300.0))
        .collect();
    (0..300)
        .map(|frame| {
            roll_steps_deg
                .iter()
                .enumerate()
                .map(|(k, step)| {
                    let step_frame = 30 + 20 * k;
                    let stepped = frame >= step_frame;
                    let turning = k % 2 == 1 && !stepped;
                    let heading_deg = 10.0 * k as f64
                        + if k % 2 == 1 {
                            0.2 * frame.min(step_frame) as f64
                        } else {
                            0.0
                        };
                    let h = heading_deg.to_radians();
                    let velocity = Vector3::new(50.0 * h.cos(), -50.0 * h.sin(), 0.0);
                    position[k] += velocity * dt;
                    let roll_deg =
                        if turning { 25.0 } else { 0.0 } + if stepped { *step } else { 0.0 };
                    Some(FlightView {
                        time_s: frame as f64 * dt,
                        position_m: position[k],
                        velocity_mps: velocity,
                        attitude: Attitude {
                            roll_deg,
                            pitch_deg: 2.0,
                            heading_deg,
                        },
                        ..base
                    })
                })
                .collect()
        })
        .collect()
}

/// Aircraft whose rotation speeds up: aircraft `k` rolls with an angular
/// acceleration of its own (3°/s² to 40°/s², both ways) and turns with
/// another, flying straight at 50 m/s (so that only the orientation makes
/// PDUs due). The receivers turn the last PDU's orientation by its angular
/// velocity, which falls behind: the error grows with the square of the
/// time since the PDU until it passes the threshold, on frames whose
/// extrapolated turn is up to a few tenths of a radian, where the screen's
/// series for `sin θ/θ` and `(1 − cos θ)/θ²` must hold. Each crossing lands
/// at its own distance above the threshold (up to a third of a degree), so
/// a screen whose estimate of the angle is off by more than that clears a
/// frame that is due. `views[frame][k]`, 300 frames at 30 Hz.
fn spinning_views() -> Vec<Vec<Option<FlightView>>> {
    let base = member_zero_view();
    let roll_accelerations_deg_s2 = [3.0, -7.0, 12.0, -18.0, 25.0, -31.0, 40.0, 9.5];
    let dt = 1.0 / 30.0;
    (0..300)
        .map(|frame| {
            let t = f64::from(frame) * dt;
            roll_accelerations_deg_s2
                .iter()
                .enumerate()
                .map(|(k, alpha)| {
                    let h0 = (40.0 * k as f64).to_radians();
                    let velocity = Vector3::new(50.0 * h0.cos(), -50.0 * h0.sin(), 0.0);
                    let turn_deg_s2 = 2.0 + 1.5 * k as f64;
                    Some(FlightView {
                        time_s: t,
                        position_m: Vector3::new(0.0, 100.0 * k as f64, 500.0) + velocity * t,
                        velocity_mps: velocity,
                        attitude: Attitude {
                            roll_deg: (0.5 * alpha * t * t + 180.0).rem_euclid(360.0) - 180.0,
                            pitch_deg: 3.0,
                            heading_deg: (40.0 * k as f64 + 0.5 * turn_deg_s2 * t * t)
                                .rem_euclid(360.0),
                        },
                        ..base
                    })
                })
                .collect()
        })
        .collect()
}

/// What [`screened_like_alone`] saw: each frame's sends as the trackers
/// updated alone made them, and how many exact views the screen asked for.
struct Screened {
    frames: Vec<Expected>,
    exact_views: usize,
    /// The trackers updated alone, after the last frame.
    alone: Vec<Tracker>,
}

/// Publishes `rows` (each frame's views, aircraft by aircraft) with
/// `publish_screened` on a fleet of `trackers`, and updates the same
/// trackers alone: every frame must send exactly the trackers' datagrams and
/// count them in its tally (invalid frames included), and at the end every
/// aircraft's counts must be its tracker's.
fn screened_like_alone(
    trackers: Vec<Tracker>,
    placement: &Placement,
    rows: &[Vec<Option<FlightView>>],
    name: &str,
) -> Screened {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let mut alone = trackers.clone();
    let mut screened = FleetPublisher::new(trackers);
    let (rx, tx) = link();
    let mut last = Vec::new();
    let exact_views = AtomicUsize::new(0);
    let mut frames = Vec::new();
    for (frame, row) in rows.iter().enumerate() {
        let e = expected_frame(&mut alone, row, placement);
        let tally = screened.publish_screened(
            &tx,
            placement,
            &mut last,
            |i| row[i].map(|v| (i, v)),
            rough,
            |i, s| {
                exact_views.fetch_add(1, Ordering::Relaxed);
                view(i, s)
            },
        );
        let what = format!("{name}, frame {frame}");
        assert_eq!(received(&rx, e.datagrams.len()), e.datagrams, "{what}");
        assert_tally(&tally, &e, &what);
        frames.push(e);
    }
    for (k, tracker) in alone.iter().enumerate() {
        assert_eq!(
            screened.counts(k),
            Some(tracker.counts()),
            "{name}: aircraft {k}"
        );
    }
    Screened {
        frames,
        exact_views: exact_views.into_inner(),
        alone,
    }
}

impl Screened {
    /// The PDUs sent for each reason over all frames.
    fn reasons(&self) -> ReasonCounts {
        let mut r = ReasonCounts::default();
        for e in &self.frames {
            r.first += e.reasons.first;
            r.position += e.reasons.position;
            r.orientation += e.reasons.orientation;
            r.heartbeat += e.reasons.heartbeat;
        }
        r
    }

    /// The frames that sent a PDU or were refused.
    fn due(&self) -> usize {
        self.frames
            .iter()
            .map(|e| e.datagrams.len() + usize::try_from(e.invalid).unwrap())
            .sum()
    }
}

/// The screen clears a frame only when the tracker would send nothing: on
/// [`stepping_views`] and [`spinning_views`], `publish_screened` sends each
/// frame exactly the datagrams of the trackers updated alone, and the
/// trackers send for their orientation many times (so the screen was asked
/// about frames that are due), while the screen still clears most frames.
#[test]
fn the_screen_clears_no_frame_whose_orientation_is_due() {
    let placement = Placement::new(GeodeticOrigin::default());
    for (name, views) in [
        ("stepping", stepping_views()),
        ("spinning", spinning_views()),
    ] {
        let fleet = trackers().into_iter().take(views[0].len()).collect();
        let run = screened_like_alone(fleet, &placement, &views, name);
        let orientation = run.reasons().orientation;
        assert!(orientation >= 7, "{name}: {orientation} orientation PDUs");
        // Most frames were cleared by the screen.
        let counts = run.alone[0].counts();
        assert!(counts.frames > 4 * counts.sent, "{name}: {counts:?}");
    }
}

/// The screen clears the frames where nothing is due (docs of
/// `publish_screened`: the exact view is made only for the aircraft the
/// screen cannot show to have nothing due; its margins are a micrometre
/// and 1e-7 in the cosine of the orientation error, so a frame of a steady
/// turn that is not due is cleared). On the fleet's steady turns, the exact
/// view is asked for at most twice per due PDU (the due frame, and the last
/// cleared frame before it, placed exactly for the rates) and once per
/// frame of an aircraft the screen cannot read (the diverged one, the first
/// frame, a frame after a gap in the input).
#[test]
fn the_screen_clears_the_frames_where_nothing_is_due() {
    let placement = Placement::new(GeodeticOrigin::default());
    let views = views();
    let frames: usize = views.iter().flatten().filter(|v| v.is_some()).count();
    let run = screened_like_alone(trackers(), &placement, &views, "steady turns");
    let (due, exact_views) = (run.due(), run.exact_views);
    assert!(frames > 10 * due, "{due} due of {frames}");
    assert!(
        exact_views <= 2 * due + 3 * OFFERED.len(),
        "{exact_views} exact views for {due} due frames of {frames}"
    );
}

/// The smallest time after a PDU at time 0 at which the heartbeat (5 s,
/// less the dead-reckoning rule's slack) is due, found through the public
/// rule itself ([`DeadReckoner::check`] of a parked aircraft, bisected over
/// the `f64`s between 4.9 and 5 s), so that a frame can land on it exactly.
fn first_heartbeat_time_s(view: &FlightView, placement: &Placement) -> f64 {
    let algorithm = DrAlgorithm::default();
    let mut reckoner = DeadReckoner::new(algorithm, DrThresholds::default()).unwrap();
    let at = |time_s: f64| placement.place(&FlightView { time_s, ..*view });
    reckoner.record_sent(WireState::new(&at(0.0), algorithm));
    let (mut quiet, mut due) = (4.9f64, 5.0f64);
    assert_eq!(reckoner.check(&at(quiet)), None);
    assert_eq!(reckoner.check(&at(due)), Some(SendReason::Heartbeat));
    while f64::from_bits(quiet.to_bits() + 1) < due {
        let mid = f64::from_bits((quiet.to_bits() + due.to_bits()) / 2);
        if reckoner.check(&at(mid)).is_some() {
            due = mid;
        } else {
            quiet = mid;
        }
    }
    due
}

/// The screen at its edges, each frame against the trackers alone (same
/// datagrams, same tally, invalid frames included):
/// * aircraft 0 flies straight at 50 m/s and reports 1e308 m/s for one
///   frame, where the last PDU's dead reckoning puts it: the exact path
///   refuses that frame and the next (their change of velocity overflows),
///   and the screen must not clear them for their position and orientation;
/// * aircraft 1 turns with thresholds of its own (0.05 m, 0.2°, 1 s), which
///   the screen, made for the fleet's, must not use to clear its frames;
/// * aircraft 2 is parked, and one of its frames lands exactly on the first
///   time the heartbeat is due, which the screen must not clear.
#[test]
fn the_screen_clears_nothing_at_its_edges() {
    let placement = Placement::new(GeodeticOrigin::default());
    let aircraft = Palmer::default_aircraft();
    let (controls, mut turning) = Palmer::fleet_member(3);
    let parked = FlightView {
        time_s: 0.0,
        velocity_mps: Vector3::zeros(),
        ..member_zero_view()
    };
    let heartbeat_s = first_heartbeat_time_s(&parked, &placement);
    let straight = |time_s: f64, velocity_mps: Vector3<f64>| FlightView {
        time_s,
        position_m: Vector3::new(0.0, 0.0, 300.0) + Vector3::new(50.0, 0.0, 0.0) * time_s,
        velocity_mps,
        ..parked
    };
    let mut trackers = trackers().into_iter().take(3).collect::<Vec<_>>();
    let tight = DrThresholds {
        position_m: 0.05,
        orientation_deg: 0.2,
        heartbeat_s: 1.0,
    };
    trackers[1] = Tracker::new(trackers[1].config().clone(), tight).unwrap();
    let rows: Vec<Vec<Option<FlightView>>> = (0..200u32)
        .map(|frame| {
            let t = f64::from(frame) / 32.0;
            turning = Palmer::step(&aircraft, &controls, &turning, 1.0 / 32.0);
            let velocity = if frame == 60 {
                Vector3::new(1e308, 0.0, 0.0)
            } else {
                Vector3::new(50.0, 0.0, 0.0)
            };
            let parked_t = if frame == 160 { heartbeat_s } else { t };
            vec![
                Some(straight(t, velocity)),
                Some(Palmer::view(&aircraft, &controls, &turning)),
                Some(FlightView {
                    time_s: parked_t,
                    ..parked
                }),
            ]
        })
        .collect();
    let run = screened_like_alone(trackers, &placement, &rows, "edges");
    let invalid: u64 = run.frames.iter().map(|e| e.invalid).sum();
    assert_eq!(invalid, 2, "the 1e308 m/s frame and the next");
    assert!(
        run.frames[160].reasons.heartbeat > 0,
        "the parked aircraft's heartbeat at {heartbeat_s} s"
    );
    assert!(
        run.alone[1].counts().sent > 10,
        "{:?}",
        run.alone[1].counts()
    );
}

/// A frame just beyond the position threshold (1 m, the default, and 0.25 m
/// for a whole fleet; at the default origin and on the equator at the prime
/// meridian, where the ECEF coordinates, and so the rounding the margin
/// covers, are largest; in five directions): an aircraft flying straight
/// (where the first PDU's dead reckoning puts it) is moved at frame 20 by the
/// smallest offset at which the rule calls its position due (found through
/// [`DeadReckoner::check`], bisected over the `f64`s between half and one
/// and a half thresholds), an error a rounding above the threshold, which
/// the exact path computes in ECEF metres and the screen relative to the
/// origin. The exact path sends
/// it; a screen whose position margin (a micrometre and 1e-13 of the
/// coordinates' size) were gone or of the wrong sign would clear it.
#[test]
fn the_screen_does_not_clear_a_frame_just_beyond_the_position_threshold() {
    let base = member_zero_view();
    let velocity = Vector3::new(40.0, -30.0, 0.0);
    let origins = [
        GeodeticOrigin::default(),
        GeodeticOrigin::new(0.0, 0.0, 0.0).unwrap(),
    ];
    let directions = [
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(-0.6, 0.8, 0.0),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
    ];
    let start = Vector3::new(0.0, 0.0, 300.0);
    let mut cases = Vec::new();
    for origin in origins {
        for position_m in [1.0, 0.25] {
            for direction in directions {
                cases.push((origin, position_m, direction));
            }
        }
    }
    for (origin, position_m, direction) in cases {
        let placement = Placement::new(origin);
        let at = |frame: u32, offset_m: f64| {
            let t = f64::from(frame) / 32.0;
            FlightView {
                time_s: t,
                position_m: start + direction * offset_m + velocity * t,
                velocity_mps: velocity,
                ..base
            }
        };
        let thresholds = DrThresholds {
            position_m,
            ..DrThresholds::default()
        };
        let algorithm = DrAlgorithm::default();
        let mut reckoner = DeadReckoner::new(algorithm, thresholds).unwrap();
        reckoner.record_sent(WireState::new(&placement.place(&at(0, 0.0)), algorithm));
        let due = |offset_m: f64| reckoner.check(&placement.place(&at(20, offset_m)));
        let (mut quiet, mut beyond) = (0.5 * position_m, 1.5 * position_m);
        assert_eq!(due(quiet), None);
        assert_eq!(due(beyond), Some(SendReason::PositionError));
        while f64::from_bits(quiet.to_bits() + 1) < beyond {
            let mid = f64::from_bits((quiet.to_bits() + beyond.to_bits()) / 2);
            if due(mid).is_some() {
                beyond = mid;
            } else {
                quiet = mid;
            }
        }
        let fleet = vec![Tracker::new(trackers()[0].config().clone(), thresholds).unwrap()];
        let rows: Vec<_> = (0..40)
            .map(|frame| vec![Some(at(frame, if frame == 20 { beyond } else { 0.0 }))])
            .collect();
        let name = format!("{origin:?}, {position_m} m, {direction}");
        let run = screened_like_alone(fleet, &placement, &rows, &name);
        assert!(
            run.frames[20].reasons.position >= 1,
            "the frame {beyond} m off is due"
        );
    }
}

/// A steady acceleration in a straight line (30 m/s, speeding up at
/// 3 m/s²) is what DRM(R,V,W) extrapolates exactly (`P₀ + V₀ Δt + ½ A₀ Δt²`
/// with the acceleration the tracker derives from the frames): after its
/// first PDU (which has no acceleration: the tracker has no frame before it)
/// and the one position PDU that follows, the aircraft sends its heartbeats
/// only, and the screen, which extrapolates the same way, clears every other
/// frame (the exact view is asked for at most twice per PDU: the due frame,
/// and the last cleared one before it).
#[test]
fn the_screen_clears_a_steady_acceleration() {
    let placement = Placement::new(GeodeticOrigin::default());
    let base = member_zero_view();
    let direction = Vector3::new(0.6, -0.8, 0.0);
    let rows: Vec<_> = (0..300)
        .map(|frame| {
            let t = f64::from(frame) / 30.0;
            vec![Some(FlightView {
                time_s: t,
                position_m: Vector3::new(0.0, 0.0, 300.0) + direction * (30.0 * t + 1.5 * t * t),
                velocity_mps: direction * (30.0 + 3.0 * t),
                ..base
            })]
        })
        .collect();
    let fleet = trackers().into_iter().take(1).collect();
    let run = screened_like_alone(fleet, &placement, &rows, "accelerating");
    let reasons = run.reasons();
    assert_eq!((reasons.position, reasons.orientation), (1, 0));
    let (due, exact_views) = (run.due(), run.exact_views);
    assert!(due <= 4, "{due} PDUs");
    assert!(
        exact_views <= 2 * due + 1,
        "{exact_views} exact views for {due} PDUs in {} frames",
        rows.len()
    );
}
