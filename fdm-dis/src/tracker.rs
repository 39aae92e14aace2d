//! Publishing flight models' aircraft: each aircraft seen through the model
//! interface's [`FlightView`], placed on WGS-84 from the run's
//! [`GeodeticOrigin`] straight into ECEF ([`Placement`]), its rates derived
//! from consecutive frames ([`Tracker`]), its PDUs counted ([`Tally`]). A
//! whole fleet of them is published by [`crate::fleet::FleetPublisher`].
//!
//! # Rates
//!
//! The model interface has no angular velocity or acceleration, and the
//! dead-reckoning algorithms want them (DRM(R,V,W) uses both). [`Tracker`]
//! derives them from consecutive frames: the acceleration is the change of
//! the ECEF velocity over the frame, the body angular velocity the rotation
//! between the two body-to-ECEF orientations (`ω = log(C_prev⁻¹ C_now) / Δt`,
//! body axes), as [`EcefState`] wants them. They are one frame's averages
//! (half a frame late); on the first frame and after the clock goes back (a
//! reset) they are zero.
//!
//! # Only what is due
//!
//! On most frames most aircraft send nothing (dead reckoning keeps the
//! receivers' picture within the thresholds; about 2 % of a turning fleet is
//! due per frame). Deciding that needs the aircraft's ECEF location and
//! orientation matrix only; its DIS Euler angles (three `atan2` and a
//! `hypot`), its rates (a rotation log) and the PDU are made for the
//! aircraft that are due. The decision and every byte sent are the ones the
//! whole computation gives (see [`Tracker::update`]).

use fdm_core::geodesy::{ned_from_model, GeodeticOrigin};
use fdm_core::model::FlightView;
use nalgebra::{Matrix3, Vector3};

use crate::dead_reckoning::{DrThresholds, SendReason};
use crate::entity::EntityConfig;
use crate::error::DisOutputError;
use crate::frames::{ned_to_ecef_rotation, EcefState};
use crate::publisher::{DatagramQueue, Due, EntityPublisher, PublisherCounts, UdpSender};

/// Where a run's model frame sits in ECEF: the flat model frame (x north,
/// y west, z up) is the tangent plane at the origin, so a model-frame
/// position is one rotation and translation away from ECEF
/// ([`GeodeticOrigin::model_to_ecef`]), and model-frame north-east-down
/// axes are the origin's local NED axes: one constant rotation to ECEF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    origin: GeodeticOrigin,
    /// `C_ecef←ned` at the origin = `C_ecef←model-NED`.
    model_ned_to_ecef: Matrix3<f64>,
}

/// One aircraft's frame placed in ECEF, before its DIS angles and rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Simulation time, seconds.
    pub time_s: f64,
    /// Location, ECEF metres.
    pub location_m: Vector3<f64>,
    /// Body-to-ECEF rotation (body axes as columns, ECEF components).
    pub body_to_ecef: Matrix3<f64>,
    /// Velocity relative to the Earth, ECEF components, m/s.
    pub velocity_m_s: Vector3<f64>,
}

impl Placed {
    /// Whether every number is finite.
    fn is_finite(&self) -> bool {
        self.time_s.is_finite()
            && self.location_m.iter().all(|v| v.is_finite())
            && self.body_to_ecef.iter().all(|v| v.is_finite())
            && self.velocity_m_s.iter().all(|v| v.is_finite())
    }

    /// The whole ECEF state with these rates (its DIS angles made here).
    fn with_rates(
        &self,
        acceleration_m_s2: Vector3<f64>,
        angular_velocity: Vector3<f64>,
    ) -> EcefState {
        EcefState::new(
            self.time_s,
            self.location_m,
            self.body_to_ecef,
            self.velocity_m_s,
            acceleration_m_s2,
            angular_velocity,
        )
    }
}

impl Placement {
    /// The placement of a model frame at `origin`.
    #[must_use]
    pub fn new(origin: GeodeticOrigin) -> Self {
        let g = origin.geodetic();
        Self {
            origin,
            model_ned_to_ecef: ned_to_ecef_rotation(g.lat_deg, g.lon_deg),
        }
    }

    /// The origin.
    #[must_use]
    pub fn origin(&self) -> &GeodeticOrigin {
        &self.origin
    }

    /// `C_ecef←ned` at the origin, which is also `C_ecef←model-NED`.
    #[must_use]
    pub fn model_ned_to_ecef(&self) -> &Matrix3<f64> {
        &self.model_ned_to_ecef
    }

    /// The aircraft seen through `view` in ECEF: location, body-to-ECEF
    /// rotation, velocity.
    ///
    /// This is the FlightGear bridge's placement (`fgnet::bridge::display`)
    /// without its detour through latitude and longitude: the bridge converts
    /// the ECEF position to geodetic coordinates and makes the attitude local
    /// there (`C_local←model`), and DIS would turn both back into ECEF with
    /// `C_ecef←local`; the product is `C_ecef←model`, applied here directly.
    /// The two agree to rounding (tested in `sim-cli`), and this costs no
    /// geodetic conversion.
    #[must_use]
    pub fn placed(&self, view: &FlightView) -> Placed {
        let c = &self.model_ned_to_ecef;
        Placed {
            time_s: view.time_s,
            location_m: self.origin.model_to_ecef(view.position_m),
            body_to_ecef: c * view.attitude.body_to_ned(),
            velocity_m_s: c * ned_from_model(view.velocity_mps),
        }
    }

    /// [`Placement::placed`] as a whole [`EcefState`] without rates (its DIS
    /// angles made).
    #[must_use]
    pub fn place(&self, view: &FlightView) -> EcefState {
        self.placed(view)
            .with_rates(Vector3::zeros(), Vector3::zeros())
    }
}

/// The rotation vector (axis × angle, radians) of a rotation matrix `r`:
/// the log that turns the rotation between two frames into an angular
/// velocity. Robust for every finite input: `(r - rᵀ)/2` gives axis × sin θ
/// and `atan2(sin θ, (trace - 1)/2)` the angle, so a rounding error that
/// puts the trace a hair above 3 (no turn at all) cannot make an `acos`
/// return NaN; a turn too small to have a direction gives the small vector
/// itself (sin θ ≈ θ).
#[must_use]
pub fn rotation_vector(r: &Matrix3<f64>) -> Vector3<f64> {
    let v = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let sin = v.norm();
    let cos = (r.trace() - 1.0) * 0.5;
    let angle = fdm_core::math::atan2(sin, cos);
    if sin > 1e-12 {
        v * (angle / sin)
    } else {
        v
    }
}

/// What the previous frame left for the rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Previous {
    pub(crate) time_s: f64,
    pub(crate) velocity_ecef_m_s: Vector3<f64>,
    pub(crate) body_to_ecef: Matrix3<f64>,
}

/// Largest velocity component, m/s, for which the rates are made only when a
/// PDU is due: a difference of two such velocities over a frame of at least
/// [`LAZY_MIN_FRAME_S`] cannot overflow, so the rates are certainly finite
/// and the state certainly sendable.
const LAZY_MAX_SPEED_M_S: f64 = 1e150;
/// Shortest frame, seconds, for which the rates are made only when due (see
/// [`LAZY_MAX_SPEED_M_S`]).
const LAZY_MIN_FRAME_S: f64 = 1e-6;

/// One aircraft's DIS output: its [`EntityPublisher`] and the previous frame
/// for the rates (see the [module documentation](self)).
#[derive(Debug, Clone)]
pub struct Tracker {
    pub(crate) publisher: EntityPublisher,
    pub(crate) previous: Option<Previous>,
}

impl Tracker {
    /// A tracker that has sent nothing yet.
    ///
    /// # Errors
    /// As [`EntityPublisher::new`].
    pub fn new(config: EntityConfig, thresholds: DrThresholds) -> Result<Self, DisOutputError> {
        Ok(Self {
            publisher: EntityPublisher::new(config, thresholds)?,
            previous: None,
        })
    }

    /// Reads a few fields spread over the tracker's memory and its PDU
    /// buffer and returns them mixed, for the fleet publisher to read ahead
    /// (through [`std::hint::black_box`]) the trackers of a piece's
    /// aircraft that take the exact path, all together: their memory comes
    /// into the cache at once. Nothing is changed; the value means nothing.
    pub(crate) fn warm(&self) -> u64 {
        let previous = self.previous.map_or(0, |p| {
            p.time_s.to_bits() ^ p.velocity_ecef_m_s.z.to_bits() ^ p.body_to_ecef[(2, 2)].to_bits()
        });
        previous ^ self.publisher.warm()
    }

    /// The publisher's counts.
    #[must_use]
    pub fn counts(&self) -> PublisherCounts {
        self.publisher.counts()
    }

    /// The entity's configuration.
    #[must_use]
    pub fn config(&self) -> &EntityConfig {
        self.publisher.config()
    }

    /// The rates of `placed` from the previous frame: zero on the first frame
    /// or when the clock did not go forwards.
    fn rates(&self, placed: &Placed) -> (Vector3<f64>, Vector3<f64>) {
        if let Some(prev) = self.previous {
            let dt = placed.time_s - prev.time_s;
            if dt > 0.0 {
                let acceleration = (placed.velocity_m_s - prev.velocity_ecef_m_s) / dt;
                let turn = prev.body_to_ecef.transpose() * placed.body_to_ecef;
                return (acceleration, rotation_vector(&turn) / dt);
            }
        }
        (Vector3::zeros(), Vector3::zeros())
    }

    fn remember(&mut self, placed: &Placed) {
        self.previous = Some(Previous {
            time_s: placed.time_s,
            velocity_ecef_m_s: placed.velocity_m_s,
            body_to_ecef: placed.body_to_ecef,
        });
    }

    /// Makes the previous frame, which the fleet screen cleared without
    /// placing it exactly, exact: `last` is that frame's view (the last one
    /// this tracker was given), and `quiet` the frames the screen cleared
    /// since this tracker last counted.
    pub(crate) fn restore_previous(
        &mut self,
        last: &FlightView,
        placement: &Placement,
        quiet: u64,
    ) {
        self.remember(&placement.placed(last));
        self.publisher.count_quiet_frames(quiet);
    }

    /// This frame's ECEF state with the rates from the previous frame (zero
    /// on the first frame or after the clock went back), remembering this
    /// frame for the next.
    pub fn with_rates(&mut self, state: EcefState) -> EcefState {
        let placed = Placed {
            time_s: state.time_s,
            location_m: state.location_m,
            body_to_ecef: state.body_to_ecef,
            velocity_m_s: state.velocity_m_s,
        };
        let (acceleration, angular_velocity) = self.rates(&placed);
        self.remember(&placed);
        EcefState {
            acceleration_m_s2: acceleration,
            angular_velocity_body_rad_s: angular_velocity,
            ..state
        }
    }

    /// Whether this frame's rates are certainly finite without making them:
    /// everything finite, and neither a frame so short nor speeds so high
    /// that their quotient could overflow.
    fn rates_certainly_finite(&self, placed: &Placed) -> bool {
        let Some(prev) = self.previous else {
            return true;
        };
        let dt = placed.time_s - prev.time_s;
        let slow = |v: &Vector3<f64>| v.iter().all(|c| c.abs() < LAZY_MAX_SPEED_M_S);
        dt.is_nan()
            || dt <= 0.0
            || (dt >= LAZY_MIN_FRAME_S
                && slow(&prev.velocity_ecef_m_s)
                && slow(&placed.velocity_m_s)
                && prev.body_to_ecef.iter().all(|c| c.is_finite()))
    }

    /// Takes this frame's view; returns the PDU if one is due.
    ///
    /// Exactly [`Tracker::with_rates`] of [`Placement::place`] given to
    /// [`EntityPublisher::update_ecef`] (same decision, same bytes, same
    /// counts, same errors), but the DIS angles and the rates are made only
    /// when a PDU is due: when the placed state and its rates are certainly
    /// finite (a state that is not takes the whole computation), the
    /// dead-reckoning decision needs the location and orientation only
    /// ([`crate::DeadReckoner::check_at`]).
    ///
    /// # Errors
    /// fdm-dis's, for a state it cannot send (a diverged model: NaN).
    pub fn update(
        &mut self,
        view: &FlightView,
        placement: &Placement,
    ) -> Result<Option<Due<'_>>, DisOutputError> {
        let placed = placement.placed(view);
        if !(placed.is_finite() && self.rates_certainly_finite(&placed)) {
            let (acceleration, angular_velocity) = self.rates(&placed);
            self.remember(&placed);
            return self
                .publisher
                .update_ecef(&placed.with_rates(acceleration, angular_velocity));
        }
        let due = self.publisher.reckoner().check_at(
            placed.time_s,
            &placed.location_m,
            &placed.body_to_ecef,
        );
        if due.is_none() {
            self.remember(&placed);
            self.publisher.count_quiet_frame();
            return Ok(None);
        }
        let (acceleration, angular_velocity) = self.rates(&placed);
        self.remember(&placed);
        self.publisher
            .update_ecef(&placed.with_rates(acceleration, angular_velocity))
    }
}

/// Why the PDUs were sent, counted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReasonCounts {
    /// The first PDU of an entity, or the first after a reset.
    pub first: u64,
    /// The dead-reckoned position was off by more than the threshold.
    pub position: u64,
    /// The dead-reckoned orientation was off by more than the threshold.
    pub orientation: u64,
    /// The heartbeat.
    pub heartbeat: u64,
}

/// Counts of sends, mergeable (a fleet's parallel batches each keep one).
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// PDUs sent (handed to the OS), one per datagram.
    pub pdus: u64,
    /// Bytes in those datagrams (UDP payload).
    pub bytes: u64,
    /// Sends that failed.
    pub failed: u64,
    /// Frames of an aircraft that could not be sent at all (a non-finite state).
    pub invalid: u64,
    /// Why the PDUs were due.
    pub reasons: ReasonCounts,
    /// The first failure's message, kept until taken.
    pub first_failure: Option<String>,
    /// Due datagrams not yet handed to the OS (a fleet's
    /// [`Tally::publish_batched`]; empty otherwise).
    pending: DatagramQueue,
}

impl Tally {
    /// Sends one due PDU through `sender` and counts it (a failure is
    /// counted, its message kept once).
    pub fn send(&mut self, sender: &UdpSender, due: &Due<'_>) {
        self.count_reason(due.reason);
        self.sent(sender, sender.send(due.bytes));
    }

    /// Counts why a PDU is due.
    fn count_reason(&mut self, reason: SendReason) {
        match reason {
            SendReason::First | SendReason::ClockReset => self.reasons.first += 1,
            SendReason::PositionError => self.reasons.position += 1,
            SendReason::OrientationError => self.reasons.orientation += 1,
            SendReason::Heartbeat => self.reasons.heartbeat += 1,
        }
    }

    /// [`Tally::send`] of a fleet's frame: the PDU is queued
    /// ([`DatagramQueue`]: sent with the previous ones of its size in one
    /// call when the queue is full or a PDU of another size comes) or at
    /// [`Tally::flush`], which the fleet's publishing calls before it returns
    /// a tally: the same datagrams, in the same order, counted the same.
    pub(crate) fn send_batched(&mut self, sender: &UdpSender, due: &Due<'_>) {
        self.count_reason(due.reason);
        let mut queue = core::mem::take(&mut self.pending);
        queue.push(sender, due.bytes, |result| self.sent(sender, result));
        self.pending = queue;
    }

    /// Hands the queued datagrams ([`Tally::send_batched`]) to the OS and
    /// counts each as [`Tally::send`] counts it.
    pub(crate) fn flush(&mut self, sender: &UdpSender) {
        let mut queue = core::mem::take(&mut self.pending);
        queue.flush(sender, |result| self.sent(sender, result));
        self.pending = queue;
    }

    /// Counts one datagram's send.
    fn sent(&mut self, sender: &UdpSender, result: Result<usize, DisOutputError>) {
        match result {
            Ok(n) => {
                self.pdus += 1;
                self.bytes += n as u64;
            }
            Err(e) => {
                self.failed += 1;
                if self.first_failure.is_none() {
                    self.first_failure = Some(format!(
                        "sending DIS to {} failed: {e}; the run goes on and counts failures",
                        sender.target()
                    ));
                }
            }
        }
    }

    /// Counts a frame of an aircraft that could not be sent (its first
    /// reason is kept as the failure message).
    pub fn invalid(&mut self, error: &DisOutputError) {
        self.invalid += 1;
        if self.first_failure.is_none() {
            self.first_failure = Some(format!(
                "an aircraft's state cannot be sent over DIS: {error}; it is skipped until it can"
            ));
        }
    }

    /// Adds `other`'s counts (and its failure message if this has none).
    pub fn merge(&mut self, other: Self) {
        // Every tally a fleet's publishing returns was flushed.
        debug_assert!(
            other.pending.is_empty(),
            "a merged tally has unsent datagrams"
        );
        self.pdus += other.pdus;
        self.bytes += other.bytes;
        self.failed += other.failed;
        self.invalid += other.invalid;
        self.reasons.first += other.reasons.first;
        self.reasons.position += other.reasons.position;
        self.reasons.orientation += other.reasons.orientation;
        self.reasons.heartbeat += other.reasons.heartbeat;
        if self.first_failure.is_none() {
            self.first_failure = other.first_failure;
        }
    }

    /// Counts an aircraft's frame without sending (the tests' sink).
    #[cfg(test)]
    pub(crate) fn publish_counts_only(&mut self, result: &Result<Option<Due<'_>>, DisOutputError>) {
        match result {
            Ok(Some(_)) => self.pdus += 1,
            Ok(None) => {}
            Err(e) => self.invalid(e),
        }
    }

    /// One aircraft's frame: [`Tracker::update`]'s result sent or counted.
    pub fn publish(&mut self, sender: &UdpSender, result: Result<Option<Due<'_>>, DisOutputError>) {
        match result {
            Ok(Some(due)) => self.send(sender, &due),
            Ok(None) => {}
            Err(e) => self.invalid(&e),
        }
    }

    /// [`Tally::publish`] through [`Tally::send_batched`] (a fleet's frame;
    /// [`Tally::flush`] before the tally is returned).
    pub(crate) fn publish_batched(
        &mut self,
        sender: &UdpSender,
        result: Result<Option<Due<'_>>, DisOutputError>,
    ) {
        match result {
            Ok(Some(due)) => self.send_batched(sender, &due),
            Ok(None) => {}
            Err(e) => {
                // The queued sends first, so that the first failure kept is
                // the one that happened first, as with `publish`.
                self.flush(sender);
                self.invalid(&e);
            }
        }
    }
}

/// One aircraft's frame as [`crate::FleetPublisher::publish_screened`]'s screen
/// reads it: what dead reckoning needs, made without the model's full view.
///
/// The time, position and velocity must be the bits of the aircraft's
/// [`FlightView`] (`time_s`, `position_m`, `velocity_mps`); `body_to_ned`
/// need only be within [`ROUGH_TOLERANCE`](crate::ROUGH_TOLERANCE), element by element, of the view's
/// [`attitude.body_to_ned()`](fdm_core::geodesy::Attitude::body_to_ned)
/// (the body-to-NED matrix of the model's flat frame), finite. That is what
/// lets a model skip its Euler angles (Palmer's attitude is a matrix made
/// from its velocity and controls, turned into three angles by three
/// `atan2` and a `hypot`, and back by three `sin_cos`) on the frames where
/// nothing is due.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rough {
    /// Simulation time, seconds (the view's bits).
    pub time_s: f64,
    /// Position in the model frame, metres (the view's bits).
    pub position_m: Vector3<f64>,
    /// Velocity in the model frame, m/s (the view's bits).
    pub velocity_mps: Vector3<f64>,
    /// Body-to-NED rotation in the model frame, within [`ROUGH_TOLERANCE`](crate::ROUGH_TOLERANCE).
    pub body_to_ned: Matrix3<f64>,
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::entity::{AircraftKind, EntityIdentity, Marking};
    use crate::frames::rotation_angle_between;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;

    /// Receives `n` datagrams on `rx` (loopback; each read is one datagram).
    fn receive(rx: &std::net::UdpSocket, n: usize) -> Vec<Vec<u8>> {
        rx.set_read_timeout(Some(std::time::Duration::from_secs(5)))
            .unwrap();
        let mut buf = vec![0_u8; 70_000];
        (0..n)
            .map(|_| {
                let got = rx.recv(&mut buf).expect("a datagram within 5 s");
                buf[..got].to_vec()
            })
            .collect()
    }

    /// Datagrams `k` of `len` bytes, each byte telling its datagram apart.
    fn datagram(k: usize, len: usize) -> Vec<u8> {
        (0..len).map(|b| (k * 7 + b) as u8).collect()
    }

    /// A fleet's queued sends (`send_batched`, `flush`) reach a receiver as
    /// the same datagrams, in the same order and counted the same, as one
    /// `send` each: runs of one size longer than a segmented call holds
    /// (64), a size change in the middle, a lone datagram, and a flush of
    /// nothing; with the OS's segmentation (Linux) and without it (the
    /// fallback, forced).
    #[test]
    fn queued_sends_are_the_datagrams_one_send_each_gives() {
        let sizes: Vec<usize> = (0..150)
            .map(|k| if k < 130 { 144 } else { 100 })
            .chain([144, 1])
            .collect();
        let dues: Vec<Vec<u8>> = sizes
            .iter()
            .enumerate()
            .map(|(k, &len)| datagram(k, len))
            .collect();
        let reasons = [
            SendReason::First,
            SendReason::PositionError,
            SendReason::OrientationError,
            SendReason::Heartbeat,
        ];
        for segmenting in [true, false] {
            let rx = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
            let sender = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
            if !segmenting {
                sender.stop_segmenting();
            }
            let mut batched = Tally::default();
            let mut one_by_one = Tally::default();
            batched.flush(&sender);
            for (k, bytes) in dues.iter().enumerate() {
                let due = Due {
                    reason: reasons[k % 4],
                    bytes,
                };
                batched.send_batched(&sender, &due);
                // The first datagram of a run waits in the queue.
                if k == 0 {
                    assert!(!batched.pending.is_empty());
                }
                one_by_one.count_reason(due.reason);
                one_by_one.pdus += 1;
                one_by_one.bytes += bytes.len() as u64;
            }
            batched.flush(&sender);
            batched.flush(&sender);
            assert_eq!(receive(&rx, dues.len()), dues, "segmenting {segmenting}");
            assert_eq!(format!("{batched:?}"), format!("{one_by_one:?}"));
            assert!(batched.pending.is_empty());
        }
    }

    /// `send_segments` declines what it cannot do in one call (nothing to
    /// split, a zero length, segmentation stopped): the caller sends those
    /// one by one.
    #[test]
    fn segmented_sends_decline_what_one_send_does() {
        let rx = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
        let sender = UdpSender::new(rx.local_addr().unwrap(), false).unwrap();
        assert_eq!(sender.send_segments(&datagram(0, 144), 144), None);
        assert_eq!(sender.send_segments(&datagram(0, 288), 0), None);
        let two = [datagram(1, 144), datagram(2, 144)].concat();
        if cfg!(target_os = "linux") {
            assert_eq!(sender.send_segments(&two, 144), Some(288));
            assert_eq!(receive(&rx, 2), vec![datagram(1, 144), datagram(2, 144)]);
        }
        sender.stop_segmenting();
        assert_eq!(sender.send_segments(&two, 144), None);
    }

    /// One segmented call carries at most 64 datagrams (Linux's
    /// `UDP_MAX_SEGMENTS`) and 65,000 bytes, and at least one datagram.
    #[test]
    fn a_segmented_call_carries_64_datagrams_or_65000_bytes() {
        use crate::publisher::segments_for;
        for (len, n) in [
            (0, 1),
            (1, 64),
            (144, 64),
            (1_015, 64),
            (1_016, 63),
            (2_000, 32),
            (32_500, 2),
            (32_501, 1),
            (65_000, 1),
            (70_000, 1),
        ] {
            assert_eq!(segments_for(len), n, "{len} bytes");
        }
    }

    /// A queued send that fails is counted per datagram with the first
    /// failure's message, as `send` counts it; an aircraft that cannot be
    /// sent after queued PDUs keeps the queued sends' failure first.
    #[test]
    fn queued_sends_that_fail_count_each_datagram() {
        let bad = UdpSender::failing();
        let mut batched = Tally::default();
        let mut one_by_one = Tally::default();
        for k in 0..70 {
            let bytes = datagram(k, 144);
            let due = Due {
                reason: SendReason::Heartbeat,
                bytes: &bytes,
            };
            batched.publish_batched(&bad, Ok(Some(due)));
            one_by_one.publish(&bad, Ok(Some(due)));
        }
        let error = || Err(DisOutputError::Io("not finite".into()));
        batched.publish_batched(&bad, error());
        one_by_one.publish(&bad, error());
        batched.flush(&bad);
        assert_eq!(one_by_one.failed, 70);
        assert!(one_by_one
            .first_failure
            .as_ref()
            .unwrap()
            .starts_with("sending DIS"));
        assert_eq!(format!("{batched:?}"), format!("{one_by_one:?}"));
    }

    /// The rotation vector against nalgebra's exact construction, 1e-12 rad
    /// (rounding of a few matrix products); identity and a matrix whose
    /// trace rounds above 3 give finite zero-ish vectors, never NaN.
    #[test]
    fn rotation_vectors() {
        use nalgebra::Rotation3;
        for w in [
            Vector3::new(0.3, -0.2, 0.1),
            Vector3::new(0.0, 0.0, 1e-9),
            Vector3::new(2.5, 1.0, -0.5),
            Vector3::new(-1e-4, 2e-4, 3e-4),
        ] {
            let r = Rotation3::from_scaled_axis(w).into_inner();
            assert!((rotation_vector(&r) - w).norm() < 1e-12, "{w}");
        }
        assert_eq!(rotation_vector(&Matrix3::identity()), Vector3::zeros());
        let mut over = Matrix3::identity();
        over[(0, 0)] = 1.0 + 1e-15;
        over[(1, 1)] = 1.0 + 1e-15;
        assert!(rotation_vector(&over).iter().all(|c| c.is_finite()));
    }

    /// Uniform numbers in [0, 1) (53 bits each) from xorshift64 seeded with
    /// `x`, for the screens' random tests.
    pub(crate) fn unit_xorshift(mut x: u64) -> impl FnMut() -> f64 {
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    pub(crate) fn tracker(thresholds: DrThresholds) -> Tracker {
        let config = EntityConfig::new(
            EntityIdentity::new(1, 1, 1).unwrap(),
            AircraftKind::CESSNA_172_SKYHAWK,
            Marking::new("T").unwrap(),
        );
        Tracker::new(config, thresholds).unwrap()
    }

    /// The lazy update against the whole computation it stands for, frame
    /// by frame, over turning fleet members, tight and loose thresholds and
    /// a heartbeat of every frame: the same decisions, the same bytes, the
    /// same counts. A diverged (NaN) frame in the middle gives the same error
    /// both ways.
    #[test]
    fn lazy_update_is_the_whole_computation() {
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        for thresholds in [
            DrThresholds::default(),
            DrThresholds {
                position_m: 0.05,
                orientation_deg: 0.2,
                heartbeat_s: 1.0,
            },
            DrThresholds {
                heartbeat_s: f64::MIN_POSITIVE,
                ..DrThresholds::default()
            },
        ] {
            for i in [0, 3, 7, 11, 1_234] {
                let (controls, mut state) = Palmer::fleet_member(i);
                let mut lazy = tracker(thresholds);
                let mut whole = tracker(thresholds);
                for frame in 0..600 {
                    state = Palmer::step(&aircraft, &controls, &state, 1.0 / 30.0);
                    let mut view = Palmer::view(&aircraft, &controls, &state);
                    if frame == 300 {
                        view.position_m.x = f64::NAN;
                    }
                    let expected = {
                        let s = whole.with_rates(placement.place(&view));
                        whole
                            .publisher
                            .update_ecef(&s)
                            .map(|d| d.map(|d| (d.reason, d.bytes.to_vec())))
                    };
                    let got = lazy
                        .update(&view, &placement)
                        .map(|d| d.map(|d| (d.reason, d.bytes.to_vec())));
                    assert_eq!(got, expected, "aircraft {i}, frame {frame}");
                }
                assert_eq!(lazy.counts(), whole.counts());
                assert!(lazy.counts().sent > 1);
            }
        }
    }

    /// The orientation screen never calls an angle above the threshold
    /// "certainly within": random rotations near the threshold.
    #[test]
    fn orientation_screen_is_conservative() {
        use nalgebra::Rotation3;
        for threshold_deg in [0.1, 3.0, 45.0, 80.0] {
            let screen = crate::dead_reckoning::screen_for_tests(threshold_deg);
            let mut next = unit_xorshift(0x9E37_79B9_7F4A_7C15);
            for _ in 0..20_000 {
                let a = Rotation3::from_scaled_axis(Vector3::new(next(), next(), next()) * 3.0)
                    .into_inner();
                let axis = Vector3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
                let angle = threshold_deg.to_radians() * (0.999_999 + 2e-6 * next());
                let b = a * Rotation3::from_scaled_axis(axis * angle).into_inner();
                if screen(&a, &b) {
                    assert!(
                        rotation_angle_between(&a, &b).to_degrees() <= threshold_deg,
                        "{threshold_deg}"
                    );
                }
            }
        }
    }
}
