//! `Fleet<Bourg>` against the scalar `fdm_core::bourg::step`.
//!
//! Tolerance: none. Every aircraft must have the bits of the scalar step after
//! every frame: the kernel performs the same f32 operations in the same order
//! and calls the same `asinf` and table look-ups (see the module docs).

use fdm_core::bourg::{
    step, Bourg, BourgAction, BourgAircraft, BourgControls, BourgState, Flap, LANES,
};
use fdm_core::script::Script;
use fdm_fleet::{Fleet, FleetError};
use serde_json::Value;

const DT: f32 = 1.0 / 30.0;

/// SplitMix64 for the random fleets.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        #[allow(clippy::cast_precision_loss)] // 24 random bits, exact
        let unit = (self.next_u64() >> 40) as f32 / (1u32 << 24) as f32;
        lo + (hi - lo) * unit
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

fn bits(s: &BourgState) -> Vec<u64> {
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

fn assert_bits(fleet: &Fleet<Bourg>, expected: &[BourgState], context: &str) {
    assert_eq!(fleet.len(), expected.len());
    for (i, (got, want)) in fleet.states().zip(expected).enumerate() {
        assert_eq!(
            bits(&got),
            bits(want),
            "{context}: aircraft {i}: {got:?} != {want:?}"
        );
    }
}

/// A reference scenario: name, script, the C++ program's final position.
type Case = (String, Script<BourgAction>, [f32; 3]);

/// The reference scenarios' frame count and cases.
fn reference() -> (u64, Vec<Case>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../reference/bourg.json");
    let text = std::fs::read_to_string(path).expect("reference/bourg.json");
    let doc: Value = serde_json::from_str(&text).expect("valid JSON");
    let frames = doc["frames"].as_u64().expect("frames");
    let cases = doc["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|c| {
            let lines: Vec<&str> = c["script"]
                .as_array()
                .expect("script")
                .iter()
                .map(|l| l.as_str().expect("line"))
                .collect();
            // Printed with 9 significant digits: exactly one f32 each.
            let p = c["cpp_final_full_precision"]["position_ft"]
                .as_array()
                .expect("position")
                .iter()
                .map(|v| {
                    v.as_f64()
                        .expect("number")
                        .to_string()
                        .parse()
                        .expect("f32")
                })
                .collect::<Vec<f32>>();
            (
                c["name"].as_str().expect("name").to_owned(),
                Script::parse(&lines.join("\n")).expect("script"),
                [p[0], p[1], p[2]],
            )
        })
        .collect();
    (frames, cases)
}

#[test]
fn bit_identical_on_the_reference_scenarios_with_their_scripts() {
    let aircraft = BourgAircraft::bourg_default();
    let (frames, cases) = reference();
    // Each scenario twice (13 aircraft with an extra no-controls one: a full
    // block and a partial one).
    let scripts: Vec<&Script<BourgAction>> = cases
        .iter()
        .chain(&cases)
        .chain(cases.iter().take(1))
        .map(|c| &c.1)
        .collect();
    let mut fleet = Fleet::<Bourg>::new(aircraft).unwrap();
    let mut scalar = Vec::new();
    for _ in &scripts {
        fleet.push(BourgState::initial(), BourgControls::initial());
        scalar.push((BourgControls::initial(), BourgState::initial()));
    }
    for frame in 1..=frames {
        for (i, (script, (controls, state))) in scripts.iter().zip(&mut scalar).enumerate() {
            *controls = controls.neutralize_surfaces();
            for action in script.actions_at(frame) {
                *controls = controls.apply(action);
            }
            fleet.set_controls(i, *controls).unwrap();
            *state = step(&aircraft, controls, state, DT);
        }
        fleet.step(DT);
        let states: Vec<_> = scalar.iter().map(|s| s.1).collect();
        assert_bits(&fleet, &states, &format!("frame {frame}"));
    }
    // And the scalar step is the C++ program's (bit-exact positions).
    for (i, (name, _, position)) in cases.iter().enumerate() {
        let s = fleet.state(i).unwrap();
        assert_eq!(
            [s.position_ft.x, s.position_ft.y, s.position_ft.z],
            *position,
            "{name}"
        );
    }
}

fn random_controls(rng: &mut Rng) -> BourgControls {
    let flap = |rng: &mut Rng| {
        [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp]
            [usize::try_from(rng.below(3)).unwrap()]
    };
    let mut c = BourgControls::initial();
    c.thrust_lb = rng.range(0.0, 3000.0);
    c.rudder_deg = [-16.0, 0.0, 16.0][usize::try_from(rng.below(3)).unwrap()];
    c.port_aileron = flap(rng);
    c.starboard_aileron = flap(rng);
    c.elevators = flap(rng);
    c.landing_flaps = rng.below(2) == 0;
    c
}

fn random_state(rng: &mut Rng) -> BourgState {
    let mut s = BourgState::initial();
    s.time_s = f64::from(rng.range(0.0, 100.0));
    s.position_ft.x = rng.range(-5000.0, 5000.0);
    s.position_ft.y = rng.range(-5000.0, 5000.0);
    s.position_ft.z = rng.range(0.0, 5000.0);
    match rng.below(4) {
        // Slow (local speeds below 1 ft/s: the carried drag direction).
        0 => {
            s.velocity_ftps.x = rng.range(-0.5, 0.5);
            s.velocity_body_ftps.x = rng.range(-0.5, 0.5);
        }
        _ => {
            s.velocity_ftps.x = rng.range(40.0, 250.0);
            s.velocity_ftps.y = rng.range(-20.0, 20.0);
            s.velocity_ftps.z = rng.range(-20.0, 20.0);
            s.velocity_body_ftps = s.velocity_ftps;
        }
    }
    s.angular_velocity_radps.x = rng.range(-0.5, 0.5);
    s.angular_velocity_radps.y = rng.range(-0.5, 0.5);
    s.angular_velocity_radps.z = rng.range(-0.5, 0.5);
    let (w, x, y, z) = (
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    let n = (w * w + x * x + y * y + z * z).sqrt();
    s.orientation = fdm_core::bourg::Quaternion::new(w / n, x / n, y / n, z / n);
    s
}

#[test]
fn bit_identical_on_random_fleets_of_any_size_and_on_every_instruction_set() {
    let aircraft = BourgAircraft::bourg_default();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for (seed, n) in [(1_u64, 1), (2, LANES - 1), (3, LANES + 1), (4, 300)] {
        let mut rng = Rng(seed);
        let mut members: Vec<(BourgControls, BourgState)> = (0..n)
            .map(|_| (random_controls(&mut rng), random_state(&mut rng)))
            .collect();
        let mut dispatched = Fleet::<Bourg>::new(aircraft).unwrap();
        for (c, s) in &members {
            dispatched.push(*s, *c);
        }
        let mut baseline = dispatched.clone();
        let mut parallel = dispatched.clone();
        for frame in 0..150 {
            if frame % 40 == 20 {
                for (i, m) in members.iter_mut().enumerate() {
                    m.0 = random_controls(&mut rng);
                    for fleet in [&mut dispatched, &mut baseline, &mut parallel] {
                        fleet.set_controls(i, m.0).unwrap();
                    }
                }
            }
            dispatched.step(DT);
            baseline.step_baseline(DT);
            pool.install(|| parallel.par_step(DT));
            for m in &mut members {
                m.1 = step(&aircraft, &m.0, &m.1, DT);
            }
            let states: Vec<_> = members.iter().map(|m| m.1).collect();
            let context = format!("seed {seed}, frame {}", frame + 1);
            assert_bits(&dispatched, &states, &format!("{context}, dispatched"));
            assert_bits(&baseline, &states, &format!("{context}, baseline"));
            assert_bits(&parallel, &states, &format!("{context}, par_step"));
        }
    }
}

#[test]
fn accessors_and_memory() {
    let aircraft = BourgAircraft::bourg_default();
    let mut fleet = Fleet::<Bourg>::new(aircraft).unwrap();
    assert!(fleet.is_empty());
    fleet.step(DT);
    let c = BourgControls::initial().apply(BourgAction::ThrustUp);
    assert_eq!(fleet.push(BourgState::initial(), c), 0);
    assert_eq!(fleet.len(), 1);
    assert_eq!(fleet.controls(0), Some(c));
    assert_eq!(fleet.state(0), Some(BourgState::initial()));
    assert_eq!(fleet.state(1), None);
    assert_eq!(
        fleet.set_state(1, &BourgState::initial()),
        Err(FleetError::OutOfRange { index: 1, len: 1 })
    );
    assert!(fleet.set_controls(1, c).is_err());
    let per = Fleet::<Bourg>::bytes_per_aircraft();
    println!("{per} bytes per Bourg aircraft");
    assert!(per <= 300, "{per}");
}

/// The pitch trim (an extension of the original: the elevators' tables
/// blended toward the trim's, `BourgControls::elevator_coefficients`) flies
/// as in the scalar step, bit for bit: trims of both signs, beyond ±1
/// (clamped), zero, and with the elevators deflected (no blend).
#[test]
fn bit_identical_with_pitch_trim() {
    let aircraft = BourgAircraft::bourg_default();
    let mut rng = Rng(77);
    let mut members: Vec<(BourgControls, BourgState)> = (0..3 * LANES + 5)
        .map(|i| {
            let mut c = random_controls(&mut rng);
            c.pitch_trim = match i % 4 {
                0 => 0.0,
                1 => rng.range(-1.5, 1.5),
                2 => rng.range(0.0, 1.0),
                _ => rng.range(-1.0, 0.0),
            };
            if i % 3 == 0 {
                c.elevators = Flap::Neutral;
            }
            (c, random_state(&mut rng))
        })
        .collect();
    assert!(members.iter().any(|m| m.0.pitch_trim > 1.0));
    let mut fleet = Fleet::<Bourg>::new(aircraft).unwrap();
    for (c, s) in &members {
        fleet.push(*s, *c);
    }
    let mut baseline = fleet.clone();
    for frame in 0..100 {
        fleet.step(DT);
        baseline.step_baseline(DT);
        for m in &mut members {
            m.1 = step(&aircraft, &m.0, &m.1, DT);
        }
        let states: Vec<_> = members.iter().map(|m| m.1).collect();
        assert_bits(&fleet, &states, &format!("trim, frame {}", frame + 1));
        assert_bits(
            &baseline,
            &states,
            &format!("trim baseline, frame {}", frame + 1),
        );
    }
}
