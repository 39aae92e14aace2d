//! Flies Palmer's Cessna 172 and Bourg's 6-DoF aircraft for 60 s each through
//! the one model interface, `fdm_core::model::Model`, and prints where they are
//! every 10 s: copy [`fly`] to fly any model, including your own.
//!
//! `cargo run -p fdm-core --example fly_both`

use fdm_core::bourg::{Bourg, BourgAction};
use fdm_core::model::{FlightStatus, FlightView, Model};
use fdm_core::palmer::{Palmer, PalmerAction};

/// Feet per metre, for the printout.
const FT_PER_M: f64 = 1.0 / fdm_core::units::METRES_PER_FOOT;

/// Flies model `M` for `seconds` at `fps` frames per second: on every frame
/// the controls' per-frame reset ([`Model::begin_frame`]), the frame's key
/// presses (`keys(frame)`, frames counted from 1), one step. Prints a line
/// every `report_every_s` seconds and returns the final view and status.
fn fly<M: Model>(
    keys: impl Fn(u32) -> Vec<M::Action>,
    seconds: u32,
    fps: u32,
    report_every_s: u32,
) -> Result<(FlightView, FlightStatus), M::StepError> {
    let aircraft = M::default_aircraft();
    let mut controls = M::initial_controls();
    let mut state = M::initial_state();
    let mut status = FlightStatus::initial(M::height_m(&state));
    let dt = M::time_step(f64::from(fps));
    println!("{} ({}):", M::TITLE, M::NAME);
    for frame in 1..=seconds * fps {
        controls = M::begin_frame(controls);
        for key in keys(frame) {
            controls = M::apply(&aircraft, controls, key);
        }
        // The checked step: same bits as `M::step`, but a non-finite state
        // is an error instead of silently propagating.
        state = M::try_step(&aircraft, &controls, &state, dt)?;
        status = status.update(M::height_m(&state), M::climb_rate_mps(&state));
        if frame % (report_every_s * fps) == 0 {
            let v = M::view(&aircraft, &controls, &state);
            println!(
                "  t {:5.1} s  height {:6.0} ft  airspeed {:5.1} m/s  heading {:5.1} deg  {}",
                v.time_s,
                v.position_m.z * FT_PER_M,
                v.airspeed_mps,
                v.attitude.heading_deg,
                status.label(),
            );
        }
    }
    Ok((M::view(&aircraft, &controls, &state), status))
}

fn main() -> Result<(), String> {
    // Palmer: full throttle (20 presses of 5 %) and 5° angle of attack on the
    // first frame; the controls keep their values, so it takes off and climbs.
    let palmer = fly::<Palmer>(
        |frame| {
            if frame == 1 {
                let mut keys = vec![PalmerAction::ThrottleUp; 20];
                keys.extend([PalmerAction::AlphaUp; 5]);
                keys
            } else {
                Vec::new()
            }
        },
        60,
        30,
        10,
    );
    // Bourg: 500 → 1000 lb thrust on the first frame, then hold the stick back
    // for 2 s (the elevators deflect only on frames with a press).
    let bourg = fly::<Bourg>(
        |frame| match frame {
            1 => vec![BourgAction::ThrustUp; 5],
            2..=61 => vec![BourgAction::PitchUp],
            _ => Vec::new(),
        },
        60,
        30,
        10,
    );
    let (p, _) = palmer.map_err(|e| format!("Palmer stopped: {e}"))?;
    let (b, _) = bourg.map_err(|e| format!("Bourg stopped: {e}"))?;
    println!(
        "after 60 s: Palmer {:.0} m north, Bourg {:.0} m north of the origin",
        p.position_m.x, b.position_m.x
    );
    Ok(())
}
