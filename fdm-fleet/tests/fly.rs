//! The fleets' whole frames with a flight status (`Fleet<Palmer>::fly` in
//! `Exact`, `Fleet<Bourg>::fly`) against the scalar `fdm_core::model::fly`, one
//! aircraft at a time.
//!
//! Tolerance: none. After every frame each aircraft's state and status must
//! be those of `fly` bit for bit, including aircraft that touch the ground
//! (safe, rough and crash landings), rest on it, take off again, and diverge:
//! the kernels step with the model's own operations and the fleets run the
//! scalar `fly` or `settle` for exactly the aircraft that need them.

use fdm_core::bourg::{Bourg, BourgControls, BourgState, Flap, Quaternion};
use fdm_core::model::{fly, FlightStatus, LandingState, Model};
use fdm_core::palmer::LANES;
use fdm_core::palmer::{Flaps, Palmer, PalmerControls, PalmerState};
use fdm_fleet::{Fleet, Precision};

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

    fn unit(&mut self) -> f64 {
        #[allow(clippy::cast_precision_loss)] // 53 random bits, exact
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        unit
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    #[allow(clippy::cast_possible_truncation)] // a random f32 is what is wanted
    fn range32(&mut self, lo: f32, hi: f32) -> f32 {
        self.range(f64::from(lo), f64::from(hi)) as f32
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

/// A status to start from: mostly the initial one for the height, some
/// aircraft already landed, crashed or diverged.
fn start_status(rng: &mut Rng, height_m: f64) -> FlightStatus {
    match rng.below(12) {
        0 => FlightStatus::Landed(LandingState::Safe),
        1 => FlightStatus::Landed(LandingState::Rough),
        2 => FlightStatus::Landed(LandingState::Crash),
        3 => FlightStatus::Diverged,
        _ => FlightStatus::initial(height_m),
    }
}

fn palmer_bits(s: &PalmerState) -> [u64; 7] {
    [
        s.time_s.to_bits(),
        s.position_m.x.to_bits(),
        s.position_m.y.to_bits(),
        s.position_m.z.to_bits(),
        s.velocity_mps.x.to_bits(),
        s.velocity_mps.y.to_bits(),
        s.velocity_mps.z.to_bits(),
    ]
}

fn bourg_bits(s: &BourgState) -> Vec<u64> {
    let mut v = vec![s.time_s.to_bits(), u64::from(s.stalling)];
    for vec in [
        s.position_ft,
        s.velocity_ftps,
        s.velocity_body_ftps,
        s.angular_velocity_radps,
    ] {
        v.extend([vec.x, vec.y, vec.z].map(|c| u64::from(c.to_bits())));
    }
    let q = s.orientation.coords;
    v.extend([q.w, q.x, q.y, q.z].map(|c| u64::from(c.to_bits())));
    v
}

/// Palmer aircraft low and descending (touchdowns of every kind), on the
/// ground (rolls, take-offs), and a few that diverge: a non-finite throttle,
/// or a speed so large that the airspeed overflows.
fn palmer_members(seed: u64, n: usize) -> Vec<(PalmerControls, PalmerState, FlightStatus)> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|i| {
            let mut controls = PalmerControls {
                throttle: rng.range(0.0, 1.0),
                alpha_deg: rng.range(-2.0, 10.0),
                bank_deg: rng.range(-20.0, 20.0),
                flaps: [Flaps::Up, Flaps::Deg20][i % 2],
                brakes: false,
            };
            let mut state = PalmerState::at_rest();
            state.time_s = rng.range(0.0, 10.0);
            match rng.below(5) {
                // On the ground, rolling or at rest.
                0 => state.velocity_mps.x = rng.range(0.0, 40.0),
                // Low, descending at up to 12 m/s.
                1..=3 => {
                    state.position_m.z = rng.range(0.0, 15.0);
                    state.velocity_mps.x = rng.range(20.0, 60.0);
                    state.velocity_mps.y = rng.range(-10.0, 10.0);
                    state.velocity_mps.z = rng.range(-12.0, 1.0);
                }
                // Already below the plane.
                _ => {
                    state.position_m.z = rng.range(-3.0, 0.0);
                    state.velocity_mps.x = rng.range(20.0, 60.0);
                    state.velocity_mps.z = rng.range(-8.0, 0.0);
                }
            }
            match i % 29 {
                7 => controls.throttle = f64::NAN,
                13 => state.velocity_mps.x = 1e154,
                19 => state.velocity_mps.y = 9e153,
                // A clock that is not finite: the state is not finite, so
                // the fleet must fly the scalar frame (which says diverged).
                23 => state.time_s = f64::INFINITY,
                _ => {}
            }
            let status = start_status(&mut rng, state.position_m.z);
            (controls, state, status)
        })
        .collect()
}

fn random_flap(rng: &mut Rng) -> Flap {
    [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp]
        [usize::try_from(rng.below(3)).unwrap()]
}

/// Bourg aircraft low and descending at various attitudes, a few on the
/// plane, and a few that diverge (a non-finite thrust, an absurd rotation).
fn bourg_members(seed: u64, n: usize) -> Vec<(BourgControls, BourgState, FlightStatus)> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|i| {
            let mut c = BourgControls::initial();
            c.thrust_lb = rng.range32(0.0, 3000.0);
            c.rudder_deg = [-16.0, 0.0, 16.0][usize::try_from(rng.below(3)).unwrap()];
            c.port_aileron = random_flap(&mut rng);
            c.starboard_aileron = random_flap(&mut rng);
            c.elevators = random_flap(&mut rng);
            c.landing_flaps = rng.below(2) == 0;
            let mut s = BourgState::initial();
            s.time_s = rng.range(0.0, 10.0);
            s.position_ft.x = rng.range32(-5000.0, 5000.0);
            s.position_ft.z = match rng.below(4) {
                0 => 0.0,
                _ => rng.range32(-5.0, 60.0),
            };
            s.velocity_ftps.x = rng.range32(60.0, 200.0);
            s.velocity_ftps.y = rng.range32(-10.0, 10.0);
            s.velocity_ftps.z = rng.range32(-40.0, 5.0);
            s.velocity_body_ftps = s.velocity_ftps;
            s.angular_velocity_radps.x = rng.range32(-0.3, 0.3);
            let (w, x, y, z) = (
                1.0,
                rng.range32(-0.1, 0.1),
                rng.range32(-0.1, 0.1),
                rng.range32(-0.1, 0.1),
            );
            let norm = (w * w + x * x + y * y + z * z).sqrt();
            s.orientation = Quaternion::new(w / norm, x / norm, y / norm, z / norm);
            match i % 23 {
                5 => c.thrust_lb = f32::INFINITY,
                11 => s.angular_velocity_radps.y = 1e19,
                17 => s.velocity_body_ftps.x = 2e18,
                _ => {}
            }
            let status = start_status(&mut rng, Bourg::height_m(&s));
            (c, s, status)
        })
        .collect()
}

/// Counts of the statuses reached, to check the cases were exercised.
#[derive(Default)]
struct Seen {
    safe: bool,
    rough: bool,
    crash: bool,
    diverged_in_flight: bool,
    airborne: bool,
}

impl Seen {
    fn note(&mut self, before: FlightStatus, after: FlightStatus) {
        self.safe |= after == FlightStatus::Landed(LandingState::Safe);
        self.rough |= after == FlightStatus::Landed(LandingState::Rough);
        self.crash |= after == FlightStatus::Landed(LandingState::Crash);
        self.airborne |= after == FlightStatus::Airborne;
        self.diverged_in_flight |=
            before != FlightStatus::Diverged && after == FlightStatus::Diverged;
    }

    fn all(&self) -> bool {
        self.safe && self.rough && self.crash && self.diverged_in_flight && self.airborne
    }
}

/// One aircraft of a test fleet: controls, state, status.
type Member<M> = (<M as Model>::Controls, <M as Model>::State, FlightStatus);

/// A fleet's three ways of flying a frame, as the test calls them.
struct FlyWays<M: fdm_fleet::FleetKernel> {
    dispatched: fn(&mut Fleet<M>, M::TimeStep),
    baseline: fn(&mut Fleet<M>, M::TimeStep),
    parallel: fn(&mut Fleet<M>, M::TimeStep),
}

/// Every aircraft of fleets of 1, a block less one, a block and three, and
/// 301 members (from `members(seed, n)`), flown 120 frames dispatched, on
/// the baseline instruction set and on two threads, against the scalar
/// `fly` after every frame, bit for bit (`bits`); every landing class,
/// airborne and divergence in flight must have been seen.
fn fleet_frames_are_fly<M, B>(
    mut fleet_of: impl FnMut() -> Fleet<M>,
    lanes: usize,
    members: fn(u64, usize) -> Vec<Member<M>>,
    bits: fn(&M::State) -> B,
    ways: &FlyWays<M>,
) where
    M: fdm_fleet::FleetKernel,
    M::State: std::fmt::Debug,
    B: PartialEq + std::fmt::Debug,
{
    let aircraft = M::default_aircraft();
    let dt = M::time_step(30.0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut seen = Seen::default();
    for (seed, n) in [(1_u64, 1), (2, lanes - 1), (3, lanes + 3), (4, 301)] {
        let mut members = members(seed, n);
        let mut fleet = fleet_of();
        for (i, (c, s, status)) in members.iter().enumerate() {
            fleet.push(*s, *c);
            fleet.set_status(i, *status).unwrap();
        }
        let mut baseline = fleet.clone();
        let mut parallel = fleet.clone();
        for frame in 1..=120 {
            (ways.dispatched)(&mut fleet, dt);
            (ways.baseline)(&mut baseline, dt);
            pool.install(|| (ways.parallel)(&mut parallel, dt));
            for (i, m) in members.iter_mut().enumerate() {
                let before = m.2;
                (m.1, m.2) = fly::<M>(&aircraft, &m.0, m.2, &m.1, dt);
                seen.note(before, m.2);
                for (what, f) in [
                    ("dispatched", &fleet),
                    ("baseline", &baseline),
                    ("par_fly", &parallel),
                ] {
                    let got = f.state(i).unwrap();
                    assert_eq!(
                        (bits(&got), f.status(i)),
                        (bits(&m.1), Some(m.2)),
                        "seed {seed}, frame {frame}, aircraft {i}, {what}: {got:?} != {:?}",
                        m.1
                    );
                }
            }
        }
        assert_eq!(fleet.statuses().count(), n);
    }
    assert!(seen.all(), "not every case was flown");
}

#[test]
fn palmer_fleet_frames_are_fly_bit_for_bit() {
    fleet_frames_are_fly(
        || Fleet::<Palmer>::new(Palmer::default_aircraft()).unwrap(),
        LANES,
        palmer_members,
        palmer_bits,
        &FlyWays {
            dispatched: |f: &mut Fleet<Palmer>, dt| f.fly(dt),
            baseline: |f: &mut Fleet<Palmer>, dt| f.fly_baseline(dt),
            parallel: |f: &mut Fleet<Palmer>, dt| f.par_fly(dt),
        },
    );
}

#[test]
fn bourg_fleet_frames_are_fly_bit_for_bit() {
    fleet_frames_are_fly(
        || Fleet::<Bourg>::new(Bourg::default_aircraft()).unwrap(),
        fdm_core::bourg::LANES,
        bourg_members,
        bourg_bits,
        &FlyWays {
            dispatched: |f: &mut Fleet<Bourg>, dt| f.fly(dt),
            baseline: |f: &mut Fleet<Bourg>, dt| f.fly_baseline(dt),
            parallel: |f: &mut Fleet<Bourg>, dt| f.par_fly(dt),
        },
    );
}

/// Above the ground and airborne, `fly` is the bare step: the demonstration
/// fleets' first frames leave every aircraft airborne with the state `step`
/// gives.
#[test]
fn airborne_frames_are_the_bare_steps() {
    use fdm_fleet::LaneFleet;
    let mut flown = <Fleet<Bourg> as LaneFleet>::demonstration(100).unwrap();
    let mut stepped = flown.clone();
    for _ in 0..30 {
        flown.fly(Bourg::time_step(30.0));
        stepped.step(Bourg::time_step(30.0));
    }
    for (a, b) in flown.states().zip(stepped.states()) {
        assert_eq!(bourg_bits(&a), bourg_bits(&b));
    }
    assert!(flown.statuses().all(|s| s == FlightStatus::Airborne));
    let mut flown = <Fleet<Palmer> as LaneFleet>::demonstration(100).unwrap();
    let mut stepped = flown.clone();
    for _ in 0..30 {
        flown
            .fly_with(Palmer::time_step(30.0), Precision::Fast)
            .unwrap();
        stepped
            .step_with(Palmer::time_step(30.0), Precision::Fast)
            .unwrap();
    }
    for (a, b) in flown.states().zip(stepped.states()) {
        assert_eq!(palmer_bits(&a), palmer_bits(&b));
    }
    assert!(flown.statuses().all(|s| s == FlightStatus::Airborne));
}

/// `par_update_controls` is `set_controls` for each index: after changing
/// every aircraft's controls both ways (1,003 aircraft: whole blocks and a
/// partial one, more than one rayon task), the fleets step to the same bits
/// and read back the same controls.
#[test]
fn par_update_controls_is_set_controls_for_each_index() {
    let n = 1003;
    let mut palmer: fdm_fleet::Fleet<Palmer> = fdm_fleet::Fleet::from_states(
        Palmer::default_aircraft(),
        (0..n).map(|i| {
            let (c, s) = Palmer::fleet_member(i);
            (s, c)
        }),
    )
    .unwrap();
    let mut one_by_one = palmer.clone();
    let change = |i: usize, mut c: PalmerControls| {
        c.bank_deg = (i % 41) as f64 - 20.0;
        c.throttle = (i % 7) as f64 / 7.0;
        c.flaps = if i.is_multiple_of(3) {
            Flaps::Deg40
        } else {
            c.flaps
        };
        c
    };
    palmer.par_update_controls(change);
    for i in 0..n {
        let c = one_by_one.controls(i).unwrap();
        one_by_one.set_controls(i, change(i, c)).unwrap();
    }
    for _ in 0..30 {
        palmer
            .par_fly_with(1.0 / 30.0, fdm_fleet::Precision::Exact)
            .unwrap();
        one_by_one
            .fly_with(1.0 / 30.0, fdm_fleet::Precision::Exact)
            .unwrap();
    }
    for i in 0..n {
        assert_eq!(palmer.controls(i), one_by_one.controls(i), "{i}");
        assert_eq!(palmer.state(i), one_by_one.state(i), "{i}");
    }

    let mut bourg: fdm_fleet::Fleet<Bourg> = fdm_fleet::Fleet::from_states(
        Bourg::default_aircraft(),
        (0..n).map(|i| {
            let (c, s) = Bourg::fleet_member(i);
            (s, c)
        }),
    )
    .unwrap();
    let mut one_by_one = bourg.clone();
    let change = |i: usize, mut c: BourgControls| {
        c.thrust_lb = (i % 30) as f32 * 100.0;
        c.elevators = if i.is_multiple_of(2) {
            Flap::TrailingEdgeUp
        } else {
            Flap::Neutral
        };
        c
    };
    bourg.par_update_controls(change);
    for i in 0..n {
        let c = one_by_one.controls(i).unwrap();
        one_by_one.set_controls(i, change(i, c)).unwrap();
    }
    for _ in 0..30 {
        bourg
            .par_fly_with(1.0 / 30.0, fdm_fleet::Precision::Exact)
            .unwrap();
        one_by_one
            .fly_with(1.0 / 30.0, fdm_fleet::Precision::Exact)
            .unwrap();
    }
    for i in 0..n {
        assert_eq!(bourg.controls(i), one_by_one.controls(i), "{i}");
        assert_eq!(bourg.state(i), one_by_one.state(i), "{i}");
    }
}

/// A fleet flown piece by piece (`Fleet::pieces_mut`: controls set, frames
/// flown and everything read back per run of blocks, the runs of several
/// sizes, on rayon's threads) is the fleet flown whole, bit for bit:
/// states, statuses and controls (compared as printed: some members' are
/// NaN), for members that land, crash and
/// diverge too. Every piece holds aircraft (`is_empty` is false: at least
/// one block each).
fn pieces_are_the_whole_fleet<M, B: PartialEq + core::fmt::Debug + Clone + Send>(
    members: &[(M::Controls, M::State, FlightStatus)],
    change: impl Fn(usize, usize, M::Controls) -> M::Controls + Sync,
    bits: impl Fn(&M::State) -> B + Sync,
) where
    M: fdm_fleet::FleetKernel,
    M::Controls: PartialEq + core::fmt::Debug + Send + Sync,
    M::State: Sync,
{
    use fdm_core::real::Real;
    use rayon::prelude::*;
    let dt = M::time_step(30.0);
    let mut whole = fdm_fleet::Fleet::<M>::try_new(M::default_aircraft()).unwrap();
    for (i, (c, s, status)) in members.iter().enumerate() {
        whole.push(*s, *c);
        whole.set_status(i, *status).unwrap();
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for blocks in [1, 3, 32, 1000] {
        let mut fleet = whole.clone();
        let mut reference = whole.clone();
        for frame in 0..40 {
            reference.update_controls(|i, c| change(frame, i, c));
            for _ in 0..2 {
                reference.fly_with(dt, Precision::Exact).unwrap();
            }
            let mut seen = vec![None; members.len()];
            pool.install(|| {
                let mut pieces = fleet.pieces_mut(blocks);
                let read: Vec<Vec<(usize, B, FlightStatus, String)>> = pieces
                    .par_iter_mut()
                    .map(|piece| {
                        piece.update_controls(|i, c| change(frame, i, c));
                        for _ in 0..2 {
                            piece.fly_with(dt, Precision::Exact).unwrap();
                        }
                        let mut out = Vec::new();
                        let first = piece.first();
                        piece.for_each(|j, s, status, c| {
                            out.push((first + j, bits(s), status, format!("{c:?}")))
                        });
                        assert_eq!(out.len(), piece.len());
                        // The same aircraft read a block at a time.
                        let mut by_block = Vec::new();
                        for (j0, count, block) in piece.blocks() {
                            assert_eq!(j0 % M::Lanes::LANES, 0);
                            for l in 0..count {
                                by_block.push((
                                    first + j0 + l,
                                    bits(&block.state(l)),
                                    block.status.as_ref()[l],
                                    format!("{:?}", block.controls.as_ref()[l]),
                                ));
                            }
                        }
                        assert_eq!(by_block, out);
                        // At least one block each: a piece is never empty.
                        assert!(!piece.is_empty(), "an empty piece at {first}");
                        out
                    })
                    .collect();
                for (i, b, status, c) in read.into_iter().flatten() {
                    assert!(seen[i].is_none(), "aircraft {i} in two pieces");
                    seen[i] = Some((b, status, c));
                }
            });
            for (i, got) in seen.into_iter().enumerate() {
                let want = (
                    bits(&reference.state(i).unwrap()),
                    reference.status(i).unwrap(),
                    format!("{:?}", reference.controls(i).unwrap()),
                );
                assert_eq!(
                    got.as_ref(),
                    Some(&want),
                    "{blocks} blocks, frame {frame}, aircraft {i}"
                );
                assert_eq!(bits(&fleet.state(i).unwrap()), want.0);
            }
        }
    }
}

#[test]
fn palmer_pieces_are_the_whole_fleet() {
    let members = palmer_members(7, 301);
    pieces_are_the_whole_fleet::<Palmer, _>(
        &members,
        |frame, i, mut c| {
            if (frame + i) % 3 == 0 {
                c.bank_deg = ((frame * 7 + i) % 41) as f64 - 20.0;
                c.throttle = ((frame + i) % 11) as f64 / 10.0;
                c.flaps = [Flaps::Up, Flaps::Deg20, Flaps::Deg40][(frame + i) % 3];
            }
            c
        },
        palmer_bits,
    );
}

#[test]
fn bourg_pieces_are_the_whole_fleet() {
    let members = bourg_members(8, 301);
    pieces_are_the_whole_fleet::<Bourg, _>(
        &members,
        |frame, i, mut c| {
            if (frame + i) % 3 == 0 {
                c.thrust_lb = ((frame + i) % 30) as f32 * 100.0;
                c.elevators = [Flap::Neutral, Flap::TrailingEdgeUp, Flap::TrailingEdgeDown]
                    [(frame * 5 + i) % 3];
            }
            c
        },
        bourg_bits,
    );
}

/// A fleet flown by `LaneFleet::par_fly_then` (in pieces of several sizes on
/// rayon's threads, each piece handed on after its frame) ends as the fleet
/// flown whole, bit for bit, and each piece's hand-over shows its aircraft
/// as they are after the frame, each aircraft in exactly one piece, in
/// order, with its payload; a piece without a payload is flown all the same.
fn flying_then_is_flying_whole<M, B: PartialEq + core::fmt::Debug + Send>(
    members: &[(M::Controls, M::State, FlightStatus)],
    bits: impl Fn(&M::State) -> B + Sync,
) where
    M: fdm_fleet::FleetKernel,
    M::State: Sync,
{
    use fdm_fleet::LaneFleet as _;
    let fps = 30.0;
    let mut whole = fdm_fleet::Fleet::<M>::try_new(M::default_aircraft()).unwrap();
    for (i, (c, s, status)) in members.iter().enumerate() {
        whole.push(*s, *c);
        whole.set_status(i, *status).unwrap();
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let n = members.len();
    for asked in [1, 20, 64, 100_000] {
        let per = fdm_fleet::Fleet::<M>::piece_aircraft(asked);
        let pieces = n.div_ceil(per);
        // The last piece gets no payload: it must be flown all the same.
        let paid = pieces.saturating_sub(1).max(1);
        let mut fleet = whole.clone();
        let mut reference = whole.clone();
        for frame in 0..30 {
            pool.install(|| fdm_fleet::LaneFleet::par_fly(&mut reference, fps, Precision::Exact))
                .unwrap();
            let got = pool
                .install(|| {
                    fleet.par_fly_then(
                        fps,
                        Precision::Exact,
                        asked,
                        (0..paid).collect(),
                        |rank, piece| {
                            assert!(piece.fly_seconds >= 0.0);
                            assert_eq!(piece.states.len(), piece.statuses.len());
                            let read: Vec<_> = piece
                                .states
                                .iter()
                                .zip(piece.statuses)
                                .map(|(s, status)| (bits(&s.unwrap()), *status))
                                .collect();
                            (rank, piece.first, read)
                        },
                    )
                })
                .unwrap();
            assert_eq!(got.len(), paid, "{asked} asked");
            let mut next = 0;
            for (k, (rank, first, read)) in got.into_iter().enumerate() {
                assert_eq!((rank, first), (k, next), "{asked} asked, frame {frame}");
                assert!(read.len() <= per && (read.len() == per || first + read.len() == n));
                for (j, (b, status)) in read.into_iter().enumerate() {
                    let i = first + j;
                    let want = (
                        bits(&reference.state(i).unwrap()),
                        reference.status(i).unwrap(),
                    );
                    assert_eq!(
                        (b, status),
                        want,
                        "{asked} asked, frame {frame}, aircraft {i}"
                    );
                }
                next = first + per;
            }
            for i in 0..n {
                assert_eq!(
                    (bits(&fleet.state(i).unwrap()), fleet.status(i)),
                    (bits(&reference.state(i).unwrap()), reference.status(i)),
                    "{asked} asked, frame {frame}, aircraft {i}"
                );
            }
        }
    }
    // A precision the kernel lacks flies nothing.
    if !<M as fdm_core::real::LaneModel>::HAS_FAST {
        let mut fleet = whole.clone();
        let result = fleet.par_fly_then(fps, Precision::Fast, 8, vec![()], |(), _| ());
        assert!(result.is_err());
        for i in 0..n {
            assert_eq!(
                bits(&fleet.state(i).unwrap()),
                bits(&whole.state(i).unwrap())
            );
        }
    }
}

#[test]
fn palmer_flying_then_is_flying_whole() {
    let members = palmer_members(9, 301);
    flying_then_is_flying_whole::<Palmer, _>(&members, palmer_bits);
}

#[test]
fn bourg_flying_then_is_flying_whole() {
    let members = bourg_members(10, 301);
    flying_then_is_flying_whole::<Bourg, _>(&members, bourg_bits);
}
