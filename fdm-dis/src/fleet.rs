//! A whole fleet published on all threads ([`FleetPublisher`]): a
//! [`Tracker`] per aircraft, each frame's aircraft in batches of
//! [`FLEET_BATCH`] on the current rayon pool, either every aircraft through
//! its tracker's exact path ([`FleetPublisher::publish`]) or first through
//! the screen (`crate::screen`), which clears from a cheap [`Rough`] frame
//! the aircraft that certainly have nothing due
//! ([`FleetPublisher::publish_screened`]). The bytes sent are the same
//! either way.

use fdm_core::model::FlightView;
use pulp::{Simd, WithSimd};
use rayon::prelude::*;

use crate::error::DisOutputError;
use crate::publisher::{Due, PublisherCounts, UdpSender};
use crate::screen::{
    Frame as ScreenFrame, RoughFrames, RoughLanes, ScreenLanes, ScreenRef, ROUGH_LANES,
};
use crate::tracker::{Placement, Rough, Tally, Tracker};

/// Where aircraft `i`'s copy is in the screen's blocks laid out for pieces
/// of `layout` aircraft (see `FleetPublisher::refs`): its block and lane.
const fn slot(i: usize, layout: usize) -> (usize, usize) {
    let k = (i / layout) * layout.div_ceil(ROUGH_LANES) * ROUGH_LANES + i % layout;
    (k / ROUGH_LANES, k % ROUGH_LANES)
}

/// The layout of the screen's blocks for pieces of `piece` aircraft: any
/// whole number of blocks a piece is the fleet's order, eight to a block.
const fn layout_for(piece: usize) -> usize {
    if piece.is_multiple_of(ROUGH_LANES) {
        ROUGH_LANES
    } else {
        piece
    }
}

/// Aircraft per rayon task of [`FleetPublisher::publish`]: large enough that
/// a task's overhead vanishes next to its aircraft, small enough that two
/// threads share a frame evenly.
pub const FLEET_BATCH: usize = 1024;

/// A fleet's DIS output: a [`Tracker`] per aircraft, aircraft `i` at index
/// `i`, published on the current rayon pool.
#[derive(Debug, Clone)]
pub struct FleetPublisher {
    trackers: Vec<Tracker>,
    /// The screen's copy of each tracker ([`FleetPublisher::publish_screened`]),
    /// [`ROUGH_LANES`] to a block, laid out so that each piece of `layout`
    /// aircraft ([`FleetPublisher::screened_pieces`]) has whole blocks of
    /// its own: aircraft `i` at [`slot`]`(i, layout)`.
    refs: Vec<ScreenLanes>,
    /// The piece size the blocks are laid out for ([`layout_for`]).
    layout: usize,
}

impl Default for FleetPublisher {
    /// A publisher of no aircraft.
    fn default() -> Self {
        Self::new(Vec::new())
    }
}

impl FleetPublisher {
    /// A publisher for these trackers (aircraft `i`'s at index `i`).
    #[must_use]
    pub fn new(trackers: Vec<Tracker>) -> Self {
        Self {
            trackers,
            refs: Vec::new(),
            layout: ROUGH_LANES,
        }
    }

    /// Aircraft published.
    #[must_use]
    pub fn len(&self) -> usize {
        self.trackers.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.trackers.is_empty()
    }

    /// Publishes one frame: aircraft `i` seen through `view(i)` (`None`: not
    /// this frame, e.g. a diverged aircraft), placed by `placement`, its PDU
    /// sent through `sender` if due. On the current rayon pool in batches
    /// of [`FLEET_BATCH`] aircraft, each batch sending as it goes (a UDP
    /// socket sends whole datagrams from any thread): the datagrams of one
    /// frame are in no particular order; each aircraft's own stay in order.
    /// Returns the frame's counts.
    pub fn publish(
        &mut self,
        sender: &UdpSender,
        placement: &Placement,
        view: impl Fn(usize) -> Option<FlightView> + Sync,
    ) -> Tally {
        self.trackers
            .par_chunks_mut(FLEET_BATCH)
            .enumerate()
            .map(|(c, trackers)| {
                let mut tally = Tally::default();
                for (k, tracker) in trackers.iter_mut().enumerate() {
                    if let Some(v) = view(c * FLEET_BATCH + k) {
                        tally.publish_batched(sender, tracker.update(&v, placement));
                    }
                }
                tally.flush(sender);
                tally
            })
            .reduce(Tally::default, |mut a, b| {
                a.merge(b);
                a
            })
    }

    /// [`FleetPublisher::publish`] with a screen: the same PDUs, bytes,
    /// counts and errors, but the full view of an aircraft (for Palmer its
    /// Euler angles' `atan2`s, `hypot`s and `sin_cos`es) and its exact
    /// dead-reckoning check are made only for the aircraft that a cheap
    /// [`Rough`] frame, screened eight at a time in structure-of-arrays form
    /// (`screen`: no transcendental function, margins wider than every
    /// rounding), cannot show to have nothing due.
    ///
    /// Aircraft `i`'s input this frame is `state(i)` (`None`: not this
    /// frame); `rough(first, states, out)` fills `out[k]` with the [`Rough`]
    /// frame of aircraft `first + k` whose input is `states[k]` (`None`
    /// where it has none, or where the model cannot make one within
    /// [`ROUGH_TOLERANCE`](crate::ROUGH_TOLERANCE): that aircraft takes the
    /// exact path), for up to [`FLEET_BATCH`] aircraft at a time (so that it
    /// can work on several per instruction); `view(i, s)` makes the exact
    /// view of aircraft `i` with input `s`.
    ///
    /// An aircraft the screen clears is counted as a quiet frame, as
    /// [`Tracker::update`] would count it; its tracker is not touched until
    /// its next exact update, which first places the last cleared frame
    /// exactly (for the rates) from its input. `last` keeps each aircraft's
    /// last input for that: pass the same buffer on every frame (it is
    /// resized to the fleet and written here), and do not mix this method
    /// with [`FleetPublisher::publish`] on one publisher.
    pub fn publish_screened<S: Copy + Send + Sync>(
        &mut self,
        sender: &UdpSender,
        placement: &Placement,
        last: &mut Vec<Option<S>>,
        state: impl Fn(usize) -> Option<S> + Sync,
        rough: impl Fn(usize, &[Option<S>], &mut [Option<Rough>]) + Sync,
        view: impl Fn(usize, &S) -> FlightView + Sync,
    ) -> Tally {
        self.screened(
            placement,
            last,
            state,
            rough,
            view,
            |tally, _, due| tally.publish_batched(sender, due),
            |tally| tally.flush(sender),
        )
    }

    /// [`FleetPublisher::publish_screened`] handing each exact update's
    /// result to `send` instead of a socket: the fleet in pieces of
    /// [`FLEET_BATCH`] aircraft ([`FleetPublisher::screened_pieces`]) on the
    /// current rayon pool, each piece's inputs read by `state`, each piece's
    /// tally given to `finish` (to send what it queued) before it is merged.
    #[allow(clippy::too_many_arguments)] // private; one closure per role
    fn screened<S: Copy + Send + Sync>(
        &mut self,
        placement: &Placement,
        last: &mut Vec<Option<S>>,
        state: impl Fn(usize) -> Option<S> + Sync,
        rough: impl Fn(usize, &[Option<S>], &mut [Option<Rough>]) + Sync,
        view: impl Fn(usize, &S) -> FlightView + Sync,
        send: impl Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>) + Sync,
        finish: impl Fn(&mut Tally) + Sync,
    ) -> Tally {
        self.screened_pieces(placement, last, FLEET_BATCH)
            .into_par_iter()
            .map(|mut piece| {
                let first = piece.first;
                let states: Vec<Option<S>> = (first..first + piece.len()).map(&state).collect();
                let mut tally = piece.run(&states, &rough, &view, &send);
                finish(&mut tally);
                tally
            })
            .reduce(Tally::default, |mut a, b| {
                a.merge(b);
                a
            })
    }

    /// The fleet as pieces of `piece` aircraft each (the last may have
    /// fewer; at least one aircraft a piece), in order, for publishing
    /// each piece screened ([`ScreenedPiece::publish`]) where and when its
    /// aircraft's inputs are at hand, e.g. on the thread that has just
    /// stepped them, while they are in its cache. Publishing every piece
    /// once is one frame of [`FleetPublisher::publish_screened`]: the same
    /// PDUs, bytes, counts and errors. `last` is as there (resized to the
    /// fleet here).
    pub fn screened_pieces<'a, S: Copy>(
        &'a mut self,
        placement: &'a Placement,
        last: &'a mut Vec<Option<S>>,
        piece: usize,
    ) -> Vec<ScreenedPiece<'a, S>> {
        let n = self.trackers.len();
        last.resize(n, None);
        let per = piece.max(1);
        self.lay_out(layout_for(per));
        // The thresholds screened for: the first tracker's (a fleet's are
        // one setting; a tracker with others is never cleared).
        let thresholds = self
            .trackers
            .first()
            .map(|t| t.publisher.reckoner().thresholds());
        let frame = ScreenFrame::new(placement, thresholds);
        self.trackers
            .chunks_mut(per)
            .zip(self.refs.chunks_mut(per.div_ceil(ROUGH_LANES)))
            .zip(last.chunks_mut(per))
            .enumerate()
            .map(|(c, ((trackers, refs), last))| ScreenedPiece {
                first: c * per,
                trackers,
                refs,
                last,
                placement,
                frame,
            })
            .collect()
    }

    /// Aircraft `i`'s tracker's counts, with the quiet frames the screen
    /// cleared since it last counted.
    #[must_use]
    pub fn counts(&self, i: usize) -> Option<PublisherCounts> {
        let mut counts = self.trackers.get(i)?.counts();
        let (b, k) = slot(i, self.layout);
        counts.frames += self.refs.get(b).map_or(0, |r| r.pending[k]);
        Some(counts)
    }

    /// Lays the screen's blocks out for pieces of `layout` aircraft
    /// ([`layout_for`]), one block more for each piece's partial block,
    /// keeping every aircraft's copy.
    fn lay_out(&mut self, layout: usize) {
        let n = self.trackers.len();
        let blocks = n.div_ceil(layout) * layout.div_ceil(ROUGH_LANES);
        if layout == self.layout && self.refs.len() == blocks {
            return;
        }
        let mut refs = vec![ScreenLanes::default(); blocks];
        if !self.refs.is_empty() {
            for i in 0..n {
                let (b, k) = slot(i, self.layout);
                let (nb, nk) = slot(i, layout);
                refs[nb].set(nk, &self.refs[b].get(k));
            }
        }
        self.refs = refs;
        self.layout = layout;
    }
}

/// A run of consecutive aircraft of a [`FleetPublisher`], borrowed for one
/// screened frame ([`FleetPublisher::screened_pieces`]).
#[derive(Debug)]
pub struct ScreenedPiece<'a, S> {
    /// The fleet index of the piece's first aircraft.
    first: usize,
    trackers: &'a mut [Tracker],
    /// The piece's blocks of the screen's copies: aircraft `first + k` at
    /// block `k / ROUGH_LANES`, lane `k % ROUGH_LANES`.
    refs: &'a mut [ScreenLanes],
    last: &'a mut [Option<S>],
    placement: &'a Placement,
    frame: ScreenFrame,
}

impl<S: Copy> ScreenedPiece<'_, S> {
    /// The fleet index of the piece's first aircraft.
    #[must_use]
    pub const fn first(&self) -> usize {
        self.first
    }

    /// Aircraft in the piece.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.trackers.len()
    }

    /// Whether the piece has no aircraft.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.trackers.is_empty()
    }

    /// Publishes this frame of the piece's aircraft, as
    /// [`FleetPublisher::publish_screened`] publishes them, on this thread:
    /// aircraft `first() + k`'s input is `states[k]` (`None`, or past the
    /// end of `states`: not this frame); `rough` and `view` are as there
    /// (`rough` is called once, for the whole piece). Due PDUs are sent
    /// through `sender` as they are made. Returns the piece's counts.
    pub fn publish(
        &mut self,
        sender: &UdpSender,
        states: &[Option<S>],
        rough: impl Fn(usize, &[Option<S>], &mut [Option<Rough>]),
        view: impl Fn(usize, &S) -> FlightView,
    ) -> Tally {
        let mut tally = self.run(states, rough, view, |tally, _, due| {
            tally.publish_batched(sender, due);
        });
        tally.flush(sender);
        tally
    }

    /// [`ScreenedPiece::publish`] with the rough frames made
    /// [`ROUGH_LANES`] aircraft at a time, field by field, by `rough`
    /// ([`RoughFrames`]: `out.ok[k]` false where an aircraft has no rough
    /// frame or the model cannot make one). The screen
    /// then reads the lanes as they are, eight aircraft per instruction,
    /// without a [`Rough`] per aircraft. The same PDUs, bytes, counts and
    /// errors as [`ScreenedPiece::publish`] with the same rough frames.
    ///
    /// The piece runs with the widest instruction set pulp finds on this
    /// CPU (as the fleets' kernels do); `rough`, when the compiler inlines
    /// it (see [`RoughFrames`]), is compiled with it too.
    pub fn publish_lanes(
        &mut self,
        sender: &UdpSender,
        states: &[Option<S>],
        rough: impl RoughFrames<S>,
        view: impl Fn(usize, &S) -> FlightView,
    ) -> Tally {
        let mut tally = self.run_lanes(states, rough, view, |tally, _, due| {
            tally.publish_batched(sender, due);
        });
        tally.flush(sender);
        tally
    }

    /// [`ScreenedPiece::publish`] handing each exact update's result to
    /// `send`: the rough frames of the whole piece made by `rough`, then
    /// screened eight at a time ([`ScreenedPiece::run_lanes`]).
    fn run(
        &mut self,
        states: &[Option<S>],
        rough: impl Fn(usize, &[Option<S>], &mut [Option<Rough>]),
        view: impl Fn(usize, &S) -> FlightView,
        send: impl Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>),
    ) -> Tally {
        let first = self.first;
        let states = &states[..states.len().min(self.trackers.len())];
        let mut roughs = vec![None; states.len()];
        rough(first, states, &mut roughs);
        self.run_lanes(
            states,
            |at: usize, group: &[Option<S>], out: &mut RoughLanes| {
                let k0 = at - first;
                for (k, r) in roughs[k0..k0 + group.len()].iter().enumerate() {
                    out.set(k, r.as_ref());
                }
            },
            view,
            send,
        )
    }

    /// [`ScreenedPiece::publish_lanes`] handing each exact update's result
    /// to `send`, with pulp's widest instruction set ([`PieceRun`]).
    fn run_lanes(
        &mut self,
        states: &[Option<S>],
        rough: impl RoughFrames<S>,
        view: impl Fn(usize, &S) -> FlightView,
        send: impl Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>),
    ) -> Tally {
        pulp::Arch::new().dispatch(PieceRun {
            piece: self,
            states,
            rough,
            view,
            send,
        })
    }

    /// The piece's frame: [`ROUGH_LANES`] aircraft at a time their rough
    /// frames, the screen's decision for all of them at once and the
    /// cleared ones taken together (their inputs kept for their next exact
    /// update); then the others, in order, through the exact path one by
    /// one (as before the screen: their last cleared frame placed exactly,
    /// then [`Tracker::update`], then the screen's copy refreshed and the
    /// input kept). Their trackers are read once ahead of that
    /// ([`Tracker::warm`]), all together, so that their memory comes into
    /// the cache at once rather than one aircraft after the other. The
    /// sends are those of the aircraft in order, as when each group's
    /// exact path followed its screen. Always inlined into [`PieceRun`]'s
    /// instruction set.
    #[inline(always)]
    fn run_groups(
        &mut self,
        states: &[Option<S>],
        mut rough: impl RoughFrames<S>,
        view: impl Fn(usize, &S) -> FlightView,
        send: impl Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>),
    ) -> Tally {
        let (first, placement, frame) = (self.first, self.placement, &self.frame);
        let states = &states[..states.len().min(self.trackers.len())];
        let mut tally = Tally::default();
        let mut lanes = RoughLanes::default();
        // The piece's aircraft (index in the piece) that the screen did not
        // clear and that have an input.
        let mut exact: Vec<usize> = Vec::with_capacity(states.len() / 16);
        for (g, ((group, refs), last)) in states
            .chunks(ROUGH_LANES)
            .zip(self.refs.iter_mut())
            .zip(self.last.chunks_mut(ROUGH_LANES))
            .enumerate()
        {
            let at = g * ROUGH_LANES;
            lanes.ok = [false; ROUGH_LANES];
            rough.rough_lanes(first + at, group, &mut lanes);
            let quiet = refs.quiet_lanes(&lanes, frame);
            let mut cleared = [false; ROUGH_LANES];
            for (k, s) in group.iter().enumerate() {
                cleared[k] = quiet[k] & s.is_some();
            }
            refs.cleared(&cleared, &lanes.time_s);
            if cleared[..group.len()].contains(&false) {
                // The cleared aircraft's inputs kept now; the others' after
                // their exact path, which reads the previous one.
                for (k, (s, l)) in group.iter().zip(last.iter_mut()).enumerate() {
                    if s.is_some() {
                        if cleared[k] {
                            *l = *s;
                        } else {
                            exact.push(at + k);
                        }
                    }
                }
            } else {
                keep_inputs(last, group);
            }
        }
        for &k in &exact {
            std::hint::black_box(self.trackers[k].warm());
        }
        for &k in &exact {
            let Some(s) = &states[k] else { continue };
            let (i, lane) = (first + k, k % ROUGH_LANES);
            let refs = &mut self.refs[k / ROUGH_LANES];
            let tracker = &mut self.trackers[k];
            let last = &mut self.last[k];
            if refs.stale[lane] {
                let pending = refs.pending[lane];
                match last {
                    Some(l) => tracker.restore_previous(&view(i, l), placement, pending),
                    // Not reached: a cleared frame's input is kept.
                    None => tracker.publisher.count_quiet_frames(pending),
                }
            }
            send(&mut tally, i, tracker.update(&view(i, s), placement));
            refs.set(lane, &ScreenRef::refresh(tracker, placement, frame));
            *last = Some(*s);
        }
        tally
    }
}

/// `last[k]` becomes `group[k]` where that is an input (`Some`); the others
/// keep theirs. One copy of the whole group when every aircraft has an
/// input (the usual frame).
#[inline(always)]
fn keep_inputs<S: Copy>(last: &mut [Option<S>], group: &[Option<S>]) {
    if last.len() == group.len() && group.iter().all(Option::is_some) {
        last.copy_from_slice(group);
    } else {
        for (l, s) in last.iter_mut().zip(group) {
            if s.is_some() {
                *l = *s;
            }
        }
    }
}

/// One piece's frame ([`ScreenedPiece::run_groups`]) as a pulp operation,
/// run by [`pulp::Arch::dispatch`] with the widest instruction set the CPU
/// has (AVX-512 on x86-64-v4), as the fleets' kernels are: the screen's
/// lanes then fill vector registers.
struct PieceRun<'p, 'a, S, R, V, F> {
    piece: &'p mut ScreenedPiece<'a, S>,
    states: &'p [Option<S>],
    rough: R,
    view: V,
    send: F,
}

impl<S, R, V, F> WithSimd for PieceRun<'_, '_, S, R, V, F>
where
    S: Copy,
    R: RoughFrames<S>,
    V: Fn(usize, &S) -> FlightView,
    F: Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>),
{
    type Output = Tally;

    #[inline(always)]
    fn with_simd<Sd: Simd>(self, _simd: Sd) -> Tally {
        self.piece
            .run_groups(self.states, self.rough, self.view, self.send)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dead_reckoning::{DrThresholds, SendReason};
    use crate::tracker::tests::tracker;
    use fdm_core::geodesy::GeodeticOrigin;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;

    /// The rough frame of a view: its time, position, velocity and attitude
    /// matrix, the bits the screen wants.
    fn rough_of(v: &FlightView) -> Rough {
        Rough {
            time_s: v.time_s,
            position_m: v.position_m,
            velocity_mps: v.velocity_mps,
            body_to_ned: v.attitude.body_to_ned(),
        }
    }

    /// An aircraft's decision as the tests compare it: its index and the
    /// datagram's reason and bytes, or the error in words.
    type Sent = (usize, Result<(SendReason, Vec<u8>), String>);

    /// A publish callback that counts as the publisher does and keeps each
    /// aircraft's decision in `got`.
    fn keep(
        got: &std::sync::Mutex<Vec<Sent>>,
    ) -> impl Fn(&mut Tally, usize, Result<Option<Due<'_>>, DisOutputError>) + Sync + '_ {
        move |tally, i, result| {
            let kept = match &result {
                Ok(Some(d)) => Some((i, Ok((d.reason, d.bytes.to_vec())))),
                Ok(None) => None,
                Err(e) => Some((i, Err(e.to_string()))),
            };
            tally.publish_counts_only(&result);
            got.lock().unwrap().extend(kept);
        }
    }

    /// Every publishing path that sends (`publish`, `publish_screened`, and
    /// the pieces' `publish` and `publish_lanes`) sends through a loopback
    /// socket exactly the datagrams its tally counts, and all four send the
    /// same datagrams, frame by frame, with the same counts: the queued sends
    /// (`DatagramQueue`, segmented by the kernel where it can) are flushed
    /// before each tally is returned.
    #[test]
    fn every_publishing_path_sends_what_it_counts() {
        use std::net::UdpSocket;
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        let thresholds = DrThresholds {
            position_m: 0.3,
            orientation_deg: 1.0,
            heartbeat_s: 1.5,
        };
        // Few enough that a frame's datagrams fit a loopback socket's
        // default receive buffer (the first frame sends one per aircraft).
        let n = 100;
        let (controls, mut states): (Vec<_>, Vec<_>) = (0..n).map(Palmer::fleet_member).unzip();
        let rough_at = |i: usize, s: &fdm_core::palmer::PalmerState| {
            rough_of(&Palmer::view(&aircraft, &controls[i], s))
        };
        let rough = |first: usize,
                     input: &[Option<fdm_core::palmer::PalmerState>],
                     out: &mut [Option<Rough>]| {
            for (k, (s, o)) in input.iter().zip(out.iter_mut()).enumerate() {
                *o = s.map(|s| rough_at(first + k, &s));
            }
        };
        let rough_lanes =
            |at: usize, group: &[Option<fdm_core::palmer::PalmerState>], out: &mut RoughLanes| {
                for (k, s) in group.iter().enumerate() {
                    out.set(k, s.map(|s| rough_at(at + k, &s)).as_ref());
                }
            };
        let view =
            |i: usize, s: &fdm_core::palmer::PalmerState| Palmer::view(&aircraft, &controls[i], s);
        let receivers: Vec<UdpSocket> = (0..4)
            .map(|_| {
                let r = UdpSocket::bind("127.0.0.1:0").unwrap();
                r.set_read_timeout(Some(std::time::Duration::from_secs(5)))
                    .unwrap();
                r
            })
            .collect();
        let senders: Vec<UdpSender> = receivers
            .iter()
            .map(|r| UdpSender::new(r.local_addr().unwrap(), false).unwrap())
            .collect();
        let trackers: Vec<Tracker> = (0..n).map(|_| tracker(thresholds)).collect();
        let mut publishers: Vec<FleetPublisher> = (0..4)
            .map(|_| FleetPublisher::new(trackers.clone()))
            .collect();
        let mut lasts: Vec<Vec<Option<fdm_core::palmer::PalmerState>>> = vec![Vec::new(); 4];
        let mut buf = [0_u8; 2048];
        let mut sent = 0;
        for frame in 0..40 {
            for (s, c) in states.iter_mut().zip(&controls) {
                *s = Palmer::step(&aircraft, c, s, 1.0 / 30.0);
            }
            let tallies = [
                publishers[0].publish(&senders[0], &placement, |i| Some(view(i, &states[i]))),
                publishers[1].publish_screened(
                    &senders[1],
                    &placement,
                    &mut lasts[1],
                    |i| Some(states[i]),
                    rough,
                    view,
                ),
                {
                    let mut tally = Tally::default();
                    for mut piece in publishers[2].screened_pieces(&placement, &mut lasts[2], 64) {
                        let first = piece.first();
                        let input: Vec<_> = (first..first + piece.len())
                            .map(|i| Some(states[i]))
                            .collect();
                        tally.merge(piece.publish(&senders[2], &input, rough, view));
                    }
                    tally
                },
                {
                    let mut tally = Tally::default();
                    for mut piece in publishers[3].screened_pieces(&placement, &mut lasts[3], 64) {
                        let first = piece.first();
                        let input: Vec<_> = (first..first + piece.len())
                            .map(|i| Some(states[i]))
                            .collect();
                        tally.merge(piece.publish_lanes(&senders[3], &input, rough_lanes, view));
                    }
                    tally
                },
            ];
            let mut frames: Vec<Vec<Vec<u8>>> = Vec::new();
            for (tally, receiver) in tallies.iter().zip(&receivers) {
                let mut got: Vec<Vec<u8>> = (0..tally.pdus)
                    .map(|_| {
                        let len = receiver
                            .recv(&mut buf)
                            .expect("a datagram the tally counts");
                        buf[..len].to_vec()
                    })
                    .collect();
                assert_eq!(got.iter().map(|d| d.len() as u64).sum::<u64>(), tally.bytes);
                assert_eq!((tally.failed, tally.invalid), (0, 0));
                got.sort();
                frames.push(got);
            }
            for (k, tally) in tallies.iter().enumerate() {
                assert_eq!(
                    format!("{tally:?}"),
                    format!("{:?}", tallies[0]),
                    "path {k}, frame {frame}"
                );
                assert_eq!(frames[k], frames[0], "path {k}, frame {frame}");
            }
            sent += tallies[0].pdus;
        }
        assert!(sent > n as u64, "{sent}");
        // Nothing more than the tallies counted.
        for receiver in &receivers {
            receiver.set_nonblocking(true).unwrap();
            assert!(receiver.recv(&mut buf).is_err());
        }
    }

    /// The screened fleet publisher against the whole computation, aircraft
    /// by aircraft and frame by frame: the same PDUs (reason and bytes), the
    /// same errors, the same counts. The rough orientations are the exact
    /// ones moved by up to 0.9 × [`ROUGH_TOLERANCE`](crate::ROUGH_TOLERANCE)
    /// in every element (and none for every 13th aircraft), over more than
    /// one batch of aircraft, tight and loose thresholds, a heartbeat of every
    /// frame, an aircraft that diverges (NaN) and one left out for some
    /// frames. Most frames are screened: the full view is made for few.
    #[test]
    fn screened_publishing_is_the_whole_computation() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        use std::sync::Mutex;
        const FRAMES: usize = 160;
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        for (thresholds, n) in [
            (DrThresholds::default(), FLEET_BATCH + 6),
            (
                DrThresholds {
                    position_m: 0.05,
                    orientation_deg: 0.2,
                    heartbeat_s: 1.0,
                },
                120,
            ),
            (
                DrThresholds {
                    heartbeat_s: f64::MIN_POSITIVE,
                    ..DrThresholds::default()
                },
                40,
            ),
        ] {
            let (controls, start): (Vec<_>, Vec<_>) = (0..n).map(Palmer::fleet_member).unzip();
            let mut whole: Vec<Tracker> = (0..n).map(|_| tracker(thresholds)).collect();
            let mut screened = FleetPublisher::new(whole.clone());
            let mut last = Vec::new();
            let mut states = start.clone();
            let views = AtomicUsize::new(0);
            for frame in 0..FRAMES {
                for (s, c) in states.iter_mut().zip(&controls) {
                    *s = Palmer::step(&aircraft, c, s, 1.0 / 30.0);
                }
                if frame == 100 {
                    states[5].position_m.x = f64::NAN;
                }
                let offered = |i: usize| (i != 7 || !(60..70).contains(&frame)).then_some(i);
                let view = |i: usize, s: &fdm_core::palmer::PalmerState| {
                    views.fetch_add(1, Ordering::Relaxed);
                    Palmer::view(&aircraft, &controls[i], s)
                };
                let noise = |i: usize, e: usize| {
                    let mut x = (i * 31 + e * 7 + frame * 131) as u64 ^ 0x9E37_79B9_7F4A_7C15;
                    x = x.wrapping_mul(0x2545_f491_4f6c_dd1d);
                    ((x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
                        * 0.9
                        * crate::ROUGH_TOLERANCE
                };
                let rough = |first: usize,
                             input: &[Option<fdm_core::palmer::PalmerState>],
                             out: &mut [Option<Rough>]| {
                    for (k, (s, o)) in input.iter().zip(out.iter_mut()).enumerate() {
                        let i = first + k;
                        *o = s.filter(|_| !i.is_multiple_of(13)).map(|s| {
                            let v = Palmer::view(&aircraft, &controls[i], &s);
                            let mut m = v.attitude.body_to_ned();
                            m.iter_mut()
                                .enumerate()
                                .for_each(|(e, x)| *x += noise(i, e));
                            Rough {
                                time_s: v.time_s,
                                position_m: v.position_m,
                                velocity_mps: v.velocity_mps,
                                body_to_ned: m,
                            }
                        });
                    }
                };
                let got = Mutex::new(Vec::<Sent>::new());
                let tally = screened.screened(
                    &placement,
                    &mut last,
                    |i| offered(i).map(|i| states[i]),
                    rough,
                    view,
                    keep(&got),
                    |_| {},
                );
                let mut got = got.into_inner().unwrap();
                got.sort_by_key(|(i, _)| *i);
                let mut expected: Vec<Sent> = Vec::new();
                for (i, t) in whole.iter_mut().enumerate() {
                    let Some(i) = offered(i) else { continue };
                    let v = Palmer::view(&aircraft, &controls[i], &states[i]);
                    match t.update(&v, &placement) {
                        Ok(Some(d)) => expected.push((i, Ok((d.reason, d.bytes.to_vec())))),
                        Ok(None) => {}
                        Err(e) => expected.push((i, Err(e.to_string()))),
                    }
                }
                assert_eq!(got, expected, "{thresholds:?}, frame {frame}");
                assert_eq!(tally.invalid, u64::from(frame >= 100), "frame {frame}");
            }
            let screened_counts: Vec<_> = (0..n).map(|i| screened.counts(i).unwrap()).collect();
            let whole_counts: Vec<_> = whole.iter().map(Tracker::counts).collect();
            assert_eq!(screened_counts, whole_counts, "{thresholds:?}");
            let views = views.into_inner();
            // The full view is made for the aircraft not cleared, and again
            // for the previous frame of those whose previous frame was.
            if thresholds.heartbeat_s > 0.1 {
                let most = n * FRAMES / if thresholds.heartbeat_s > 2.0 { 5 } else { 3 };
                assert!(views < most, "{views} views for {thresholds:?}");
            }
        }
    }

    /// Pieces of any size, published one after the other
    /// ([`FleetPublisher::screened_pieces`], [`ScreenedPiece`]), are the
    /// screened publisher's frame: the same PDUs in the same order per
    /// aircraft, the same counts, with a diverged aircraft and inputs left
    /// out (`None`, or a piece's inputs cut short).
    #[test]
    fn pieces_of_any_size_are_the_screened_frame() {
        const FRAMES: usize = 120;
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        let thresholds = DrThresholds {
            position_m: 0.2,
            orientation_deg: 1.0,
            heartbeat_s: 2.0,
        };
        let n = 300;
        let (controls, start): (Vec<_>, Vec<_>) = (0..n).map(Palmer::fleet_member).unzip();
        let rough = |first: usize,
                     input: &[Option<fdm_core::palmer::PalmerState>],
                     out: &mut [Option<Rough>]| {
            for (k, (s, o)) in input.iter().zip(out.iter_mut()).enumerate() {
                *o = s
                    .filter(|_| !(first + k).is_multiple_of(11))
                    .map(|s| rough_of(&Palmer::view(&aircraft, &controls[first + k], &s)));
            }
        };
        let view =
            |i: usize, s: &fdm_core::palmer::PalmerState| Palmer::view(&aircraft, &controls[i], s);
        let trackers: Vec<Tracker> = (0..n).map(|_| tracker(thresholds)).collect();
        // 13: more than a block and not a whole number of them (the
        // layout of pieces whose blocks' count is rounded up).
        for per in [1, 7, 13, 64, n + 5] {
            let mut whole = FleetPublisher::new(trackers.clone());
            let mut pieces = FleetPublisher::new(trackers.clone());
            let (mut last_whole, mut last_pieces) = (Vec::new(), Vec::new());
            let mut states = start.clone();
            let mut pieces_seen = 0;
            for frame in 0..FRAMES {
                for (s, c) in states.iter_mut().zip(&controls) {
                    *s = Palmer::step(&aircraft, c, s, 1.0 / 30.0);
                }
                if frame == 50 {
                    states[3].velocity_mps.y = f64::NAN;
                }
                let offered =
                    |i: usize| (i % 5 != 2 || !(30..40).contains(&frame)).then(|| states[i]);
                // The last aircraft of each piece of more than one aircraft
                // is left out on frames 60..70 by cutting the piece's
                // inputs short; the whole publisher is told `None`.
                let cut = |len: usize| usize::from(len > 1 && (60..70).contains(&frame));
                let last_of_piece = |i: usize| (i + 1).is_multiple_of(per) || i + 1 == n;
                let piece_len = |i: usize| per.min(n - i / per * per);
                let offered_whole =
                    |i: usize| offered(i).filter(|_| !(last_of_piece(i) && cut(piece_len(i)) == 1));
                let expected = std::sync::Mutex::new(Vec::new());
                let want = whole.screened(
                    &placement,
                    &mut last_whole,
                    offered_whole,
                    rough,
                    view,
                    keep(&expected),
                    |_| {},
                );
                let got = std::sync::Mutex::new(Vec::new());
                let mut tally = Tally::default();
                for mut piece in pieces.screened_pieces(&placement, &mut last_pieces, per) {
                    pieces_seen += 1;
                    let first = piece.first();
                    let end = first + piece.len() - cut(piece.len());
                    let input: Vec<_> = (first..end).map(offered).collect();
                    tally.merge(piece.run(&input, rough, view, keep(&got)));
                }
                let mut expected = expected.into_inner().unwrap();
                let mut got = got.into_inner().unwrap();
                expected.sort_by_key(|(i, _)| *i);
                got.sort_by_key(|(i, _)| *i);
                assert!(frame > 0 || got.len() == n);
                assert_eq!(got, expected, "pieces of {per}, frame {frame}");
                assert_eq!(
                    format!("{tally:?}"),
                    format!("{want:?}"),
                    "pieces of {per}, frame {frame}"
                );
            }
            assert_eq!(pieces_seen, FRAMES * n.div_ceil(per));
            let a: Vec<_> = (0..n).map(|i| pieces.counts(i).unwrap()).collect();
            let b: Vec<_> = (0..n).map(|i| whole.counts(i).unwrap()).collect();
            assert_eq!(a, b, "pieces of {per}");
        }
    }

    /// The screen's blocks are laid out for the pieces asked for
    /// (`FleetPublisher::lay_out`): a publisher cut into pieces of a
    /// different size every frame (7, 1024, 5, 64, 1, …: blocks laid out
    /// again each time, every aircraft's copy, stale flag and pending
    /// count kept) publishes what one cut the same way every frame
    /// publishes, aircraft by aircraft, with the same counts; and a
    /// default publisher has no aircraft.
    #[test]
    fn pieces_of_changing_sizes_keep_the_screens_copies() {
        const FRAMES: usize = 90;
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        let thresholds = DrThresholds {
            position_m: 0.3,
            orientation_deg: 1.0,
            heartbeat_s: 1.5,
        };
        let n = 150;
        let (controls, start): (Vec<_>, Vec<_>) = (0..n).map(Palmer::fleet_member).unzip();
        let rough = |first: usize,
                     input: &[Option<fdm_core::palmer::PalmerState>],
                     out: &mut [Option<Rough>]| {
            for (k, (s, o)) in input.iter().zip(out.iter_mut()).enumerate() {
                *o = s.map(|s| rough_of(&Palmer::view(&aircraft, &controls[first + k], &s)));
            }
        };
        let view =
            |i: usize, s: &fdm_core::palmer::PalmerState| Palmer::view(&aircraft, &controls[i], s);
        let trackers: Vec<Tracker> = (0..n).map(|_| tracker(thresholds)).collect();
        let mut fixed = FleetPublisher::new(trackers.clone());
        let mut changing = FleetPublisher::new(trackers);
        let (mut last_fixed, mut last_changing) = (Vec::new(), Vec::new());
        let mut states = start;
        let mut quiet = 0;
        for frame in 0..FRAMES {
            for (s, c) in states.iter_mut().zip(&controls) {
                *s = Palmer::step(&aircraft, c, s, 1.0 / 30.0);
            }
            let offered = |i: usize| (i % 7 != 3 || frame % 4 != 1).then(|| states[i]);
            let frame_of = |publisher: &mut FleetPublisher, last: &mut Vec<_>, per: usize| {
                let got = std::sync::Mutex::new(Vec::new());
                for mut piece in publisher.screened_pieces(&placement, last, per) {
                    let first = piece.first();
                    let input: Vec<_> = (first..first + piece.len()).map(offered).collect();
                    piece.run(&input, rough, view, keep(&got));
                }
                let mut got = got.into_inner().unwrap();
                got.sort_by_key(|(i, _)| *i);
                got
            };
            let want = frame_of(&mut fixed, &mut last_fixed, 7);
            // 5 then 10: two layouts with the same number of blocks
            // (30) and different slots, so a layout kept by mistake shows.
            let per = [7, FLEET_BATCH, 5, 10, 13, 64, 1, 8, 150][frame % 9];
            let got = frame_of(&mut changing, &mut last_changing, per);
            assert_eq!(got, want, "frame {frame}, pieces of {per}");
            quiet += n - want.len();
        }
        let a: Vec<_> = (0..n).map(|i| changing.counts(i).unwrap()).collect();
        let b: Vec<_> = (0..n).map(|i| fixed.counts(i).unwrap()).collect();
        assert_eq!(a, b);
        assert!(quiet > n * FRAMES / 2, "{quiet}");
        let none = FleetPublisher::default();
        assert!(none.is_empty() && none.counts(0).is_none());
    }

    /// Frames far shorter than the tracker's lazy-rates bound (a clock
    /// started at 0 and advanced by subnormal steps, the velocity changing
    /// by 1 m/s a frame): the exact path's rates overflow and it reports
    /// the state as unsendable; the screen must not clear those frames as
    /// quiet. Same results, frame by frame, as the whole computation.
    #[test]
    fn screened_publishing_does_not_clear_frames_shorter_than_the_lazy_bound() {
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();
        let (controls, start) = Palmer::fleet_member(0);
        let base = Palmer::view(&aircraft, &controls, &start);
        let mut whole = tracker(DrThresholds::default());
        let mut screened = FleetPublisher::new(vec![whole.clone()]);
        let mut last = Vec::new();
        let mut unsendable = 0;
        for frame in 0..6_u32 {
            let mut v = base;
            // 0, 1e-310, 2e-310, ... s: frames of 1e-310 s.
            v.time_s = f64::from(frame) * 1e-310;
            v.velocity_mps.x += f64::from(frame);
            let rough = |_: usize, input: &[Option<FlightView>], out: &mut [Option<Rough>]| {
                for (s, o) in input.iter().zip(out.iter_mut()) {
                    *o = s.map(|s| Rough {
                        time_s: s.time_s,
                        position_m: s.position_m,
                        velocity_mps: s.velocity_mps,
                        body_to_ned: s.attitude.body_to_ned(),
                    });
                }
            };
            let got = std::sync::Mutex::new(Vec::new());
            screened.screened(
                &placement,
                &mut last,
                |_| Some(v),
                rough,
                |_, s| *s,
                |tally, _, result| {
                    let kept = match &result {
                        Ok(d) => d.as_ref().map(|d| Ok(d.bytes.to_vec())),
                        Err(e) => Some(Err(e.to_string())),
                    };
                    got.lock().unwrap().extend(kept);
                    tally.publish_counts_only(&result);
                },
                |_| {},
            );
            let expected = match whole.update(&v, &placement) {
                Ok(Some(d)) => vec![Ok(d.bytes.to_vec())],
                Ok(None) => vec![],
                Err(e) => {
                    unsendable += 1;
                    vec![Err(e.to_string())]
                }
            };
            // Quiet frames (cleared, or not due on the exact path) send
            // nothing; PDUs and errors must be the same.
            assert_eq!(got.into_inner().unwrap(), expected, "frame {frame}");
        }
        assert!(
            unsendable > 0,
            "the frames must overflow the exact path's rates"
        );
        assert_eq!(screened.counts(0).unwrap(), whole.counts());
    }
}
