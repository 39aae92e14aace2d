//! A mixed fleet of 10 000 aircraft (both models, varied controls, states,
//! scripts and key presses) in one world: the parallel systems give exactly
//! the bits of the sequential ones, and the world ends up as if each aircraft
//! had been flown alone with `fdm-core`.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use std::sync::Arc;

use fdm_core::bourg::{self, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{self, Flaps, PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::{Script, ScriptAction};
use fdm_ecs::components::{Attitude, Geodetic, ScriptInput};
use fdm_ecs::{Entity, Execution, Resources, Simulation};
use fdm_tests::ecs::{bourg_bits, bourg_controls_bits, palmer_bits};

const FLEET: usize = 10_000;
/// Few frames keep the debug-mode test within seconds.
const FRAMES: u64 = 3;

#[derive(Clone, Copy)]
enum Plane {
    Palmer(Entity),
    Bourg(Entity),
}

/// The same fleet, deterministically varied by index.
fn build(execution: Execution) -> (Simulation, Vec<Plane>) {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap().with_execution(execution));
    let cessna = Arc::new(PalmerAircraft::cessna_172());
    let bourg = Arc::new(BourgAircraft::bourg_default());
    let scripts: Vec<Arc<Script<BourgAction>>> = [
        "1-2 thrust-up\n2-3 pitch-up\n",
        "1-3 roll-left\n3-3 flaps-down\n",
        "1-1 yaw-right\n2-3 thrust-down\n",
    ]
    .iter()
    .map(|text| Arc::new(Script::parse(text).unwrap()))
    .collect();

    let planes = (0..FLEET)
        .map(|i| {
            let k = i as f64;
            if i % 2 == 0 {
                let controls = PalmerControls {
                    throttle: (i % 21) as f64 / 20.0,
                    alpha_deg: (i % 37) as f64 - 16.0,
                    bank_deg: (i % 41) as f64 - 20.0,
                    flaps: [Flaps::Up, Flaps::Deg20, Flaps::Deg40][i % 3],
                    brakes: false,
                };
                let state = PalmerState {
                    time_s: 0.0,
                    position_m: [k * 7.0, -k * 3.0, (i % 500) as f64].into(),
                    velocity_mps: [30.0 + (i % 29) as f64, (i % 11) as f64 - 5.0, 0.0].into(),
                };
                Plane::Palmer(sim.spawn::<Palmer>(Arc::clone(&cessna), controls, state))
            } else {
                let mut controls = BourgControls::initial();
                controls.thrust_lb = (i % 31) as f32 * 100.0;
                let mut state = BourgState::initial();
                state.position_ft.y = (i % 1000) as f32 * 10.0;
                state.velocity_ftps.x += (i % 17) as f32;
                let e = sim.spawn::<Bourg>(Arc::clone(&bourg), controls, state);
                if i % 3 != 0 {
                    sim.set_script(e, Arc::clone(&scripts[i % scripts.len()]))
                        .unwrap();
                }
                Plane::Bourg(e)
            }
        })
        .collect();
    (sim, planes)
}

/// The key aircraft `i` presses on `frame`, if any (the same for every run).
fn palmer_key(i: usize, frame: u64) -> Option<PalmerAction> {
    let all = PalmerAction::ALL;
    matches!((i as u64 + frame) % 5, 0).then(|| all[(i + frame as usize) % all.len()])
}

/// See [`palmer_key`].
fn bourg_key(i: usize, frame: u64) -> Option<BourgAction> {
    let all = BourgAction::ALL;
    matches!((i as u64 + frame) % 5, 0).then(|| all[(i * 7 + frame as usize) % all.len()])
}

fn press_keys(sim: &mut Simulation, planes: &[Plane], frame: u64) {
    for (i, plane) in planes.iter().enumerate() {
        match *plane {
            Plane::Palmer(e) => {
                if let Some(key) = palmer_key(i, frame) {
                    sim.push_input(e, key).unwrap();
                }
            }
            Plane::Bourg(e) => {
                if let Some(key) = bourg_key(i, frame) {
                    sim.push_input(e, key).unwrap();
                }
            }
        }
    }
}

/// Every bit Place wrote for an entity.
fn display_bits(sim: &Simulation, e: Entity) -> Vec<u64> {
    let g: Geodetic = sim.get(e).unwrap();
    let a: Attitude = sim.get(e).unwrap();
    [
        g.lat_deg,
        g.lon_deg,
        g.alt_m,
        a.roll_deg,
        a.pitch_deg,
        a.heading_deg,
    ]
    .iter()
    .map(|x| x.to_bits())
    .collect()
}

#[test]
fn ten_thousand_mixed_aircraft_parallel_is_bit_identical_to_sequential() {
    let (mut seq, planes) = build(Execution::Sequential);
    let (mut par, par_planes) = build(Execution::Parallel);
    let initial: Vec<_> = planes
        .iter()
        .map(|p| match *p {
            Plane::Palmer(e) => palmer_bits(&seq.state::<Palmer>(e).unwrap()).to_vec(),
            Plane::Bourg(e) => bourg_bits(&seq.state::<Bourg>(e).unwrap())
                .into_iter()
                .map(u64::from)
                .collect(),
        })
        .collect();

    for frame in 1..=FRAMES {
        press_keys(&mut seq, &planes, frame);
        press_keys(&mut par, &par_planes, frame);
        seq.run_frame();
        par.run_frame();
    }

    let mut moved = 0;
    for (i, (plane, par_plane)) in planes.iter().zip(&par_planes).enumerate() {
        match (*plane, *par_plane) {
            (Plane::Palmer(s), Plane::Palmer(p)) => {
                let state = seq.state::<Palmer>(s).unwrap();
                assert_eq!(
                    palmer_bits(&state),
                    palmer_bits(&par.state::<Palmer>(p).unwrap()),
                    "#{i}"
                );
                assert_eq!(seq.controls::<Palmer>(s), par.controls::<Palmer>(p), "#{i}");
                moved += usize::from(palmer_bits(&state).to_vec() != initial[i]);
            }
            (Plane::Bourg(s), Plane::Bourg(p)) => {
                let state = seq.state::<Bourg>(s).unwrap();
                assert_eq!(
                    bourg_bits(&state),
                    bourg_bits(&par.state::<Bourg>(p).unwrap()),
                    "#{i}"
                );
                assert_eq!(
                    bourg_controls_bits(&seq.controls::<Bourg>(s).unwrap()),
                    bourg_controls_bits(&par.controls::<Bourg>(p).unwrap()),
                    "#{i}"
                );
                let bits: Vec<u64> = bourg_bits(&state).into_iter().map(u64::from).collect();
                moved += usize::from(bits != initial[i]);
            }
            _ => panic!("fleets built differently"),
        }
        let (s, p) = match (*plane, *par_plane) {
            (Plane::Palmer(s), Plane::Palmer(p)) | (Plane::Bourg(s), Plane::Bourg(p)) => (s, p),
            _ => unreachable!(),
        };
        assert_eq!(display_bits(&seq, s), display_bits(&par, p), "#{i}");
    }
    assert_eq!(moved, FLEET, "every aircraft was stepped");
}

#[test]
fn fleet_members_fly_as_if_alone() {
    // The parallel fleet against fdm-core directly, for a sample of aircraft.
    let (mut par, planes) = build(Execution::Parallel);
    let (fresh, _) = build(Execution::Sequential); // initial components
    for frame in 1..=FRAMES {
        press_keys(&mut par, &planes, frame);
        par.run_frame();
    }

    let cessna = PalmerAircraft::cessna_172();
    let airframe = BourgAircraft::bourg_default();
    let res = *par.resources();
    for i in (0..FLEET).step_by(97) {
        match planes[i] {
            Plane::Palmer(e) => {
                let mut c = fresh.controls::<Palmer>(e).unwrap();
                let mut s = fresh.state::<Palmer>(e).unwrap();
                for frame in 1..=FRAMES {
                    if let Some(key) = palmer_key(i, frame) {
                        c = c.apply(key);
                    }
                    s = palmer::step(&cessna, &c, &s, res.time_step::<Palmer>());
                }
                assert_eq!(
                    palmer_bits(&s),
                    palmer_bits(&par.state::<Palmer>(e).unwrap()),
                    "#{i}"
                );
            }
            Plane::Bourg(e) => {
                let mut c = fresh.controls::<Bourg>(e).unwrap();
                let mut s = fresh.state::<Bourg>(e).unwrap();
                let script = par.get::<ScriptInput<BourgAction>>(e);
                for frame in 1..=FRAMES {
                    c = c.neutralize_surfaces();
                    for action in script.iter().flat_map(|s| s.0.actions_at(frame)) {
                        c = c.apply(action);
                    }
                    if let Some(key) = bourg_key(i, frame) {
                        c = c.apply(key);
                    }
                    s = bourg::step(&airframe, &c, &s, res.time_step::<Bourg>());
                }
                assert_eq!(
                    bourg_bits(&s),
                    bourg_bits(&par.state::<Bourg>(e).unwrap()),
                    "#{i}"
                );
            }
        }
    }
}
